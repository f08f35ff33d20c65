// ecsim's distributed clocks through the real binary (labels netns and dc,
// needs root): an ARMW of the reference clock's system time sent from the
// MAIN probe, then `ecsim ctl dc` and `dc --json` read back: the reference
// the master chose, the default drift, the JSON's contract names.

#include <catch2/catch.hpp>
#include <google/protobuf/struct.pb.h>
#include <google/protobuf/util/json_util.h>

#include <cmath>

#include "ecsim_bench.hpp"
#include "test_frames.hpp"

using namespace ecpair;
using namespace ecpair::test;
using wire::Command;
using wire::DatagramHeader;

TEST_CASE("ecsim's clocks: an ARMW from the wire makes its reference, ecsim ctl dc --json tells the truth",
          "[netns][ecsim][dc]") {
    EcsimBench bench;
    // The ENI's cyclic "DC; ARMW; System Time Register": ADP of slave 2 (slave 1, the IMU, has no DC).
    TestFrame armw = ethercat_frame({DatagramSpec{Command::Armw, DatagramHeader::physical(0xFFFF, 0x0910), {0, 0, 0, 0}}});
    REQUIRE(bench.probe(true).send(armw.bytes()));
    TestFrame back;
    const auto received = bench.probe(false).receive(back.buffer, kHangGuard);
    REQUIRE(received);
    REQUIRE(received->has_value());
    back.size = (*received)->size;
    CHECK(wkc_of(back) == 5);  // slave 2 read, the others written (the IMU too: its reserved registers count)

    const auto [status, json] = bench.ctl("dc --json");
    CHECK(status == 0);
    INFO(json);
    google::protobuf::Struct report;
    REQUIRE(google::protobuf::util::JsonStringToMessage(json, &report).ok());
    const auto& fields = report.fields();
    CHECK(fields.at("reference").number_value() == 2);
    CHECK(fields.at("reference_from").string_value() == "master");
    CHECK(fields.at("sync0_missed").number_value() == 0);
    const auto& slaves = fields.at("slaves").list_value().values();
    REQUIRE(slaves.size() == 5);
    CHECK(slaves[0].struct_value().fields().at("dc").string_value() == "none");
    for (const auto& slave : slaves) {
        CHECK(std::abs(slave.struct_value().fields().at("drift_ppb").number_value()) <= 25'000);  // the default
    }
    const auto text = bench.ctl("dc");
    CHECK(text.first == 0);
    CHECK_THAT(text.second, Catch::StartsWith("ok reference=slave 2 (read by the master's ARMW/FRMW)"));
    CHECK(bench.ctl("dc reset").first == 0);
}
