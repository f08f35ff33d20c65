// Bounded logs under a persistent fault (issue 29 item 3), with the real
// ecpaird on ecsim: a single master on a line, the cable after slave 2 cut
// for ten seconds, so every cycle's datagrams miss the WKC of slaves 3 and 4.
// The log must say so when it starts, summarise at most once a second and
// say when it ended - about a dozen lines, not 10 000 - and the counts the
// operator API reports must add up to the master's WKC error counter.

#include <algorithm>
#include <fstream>
#include <sstream>

#include <catch2/catch.hpp>
#include <fmt/format.h>

#include "ecpair/sim/eni_generator.hpp"
#include "ecpaird_process.hpp"
#include "ecsim_process.hpp"
#include "ring_topology.hpp"
#include "temp_dir.hpp"

using namespace ecpair::test;
using namespace std::chrono_literals;
using ecpair::control::EventMessage;
using ecpair::control::StatusReply;

namespace {

constexpr auto kReachOp = 30s;
constexpr auto kFaultHeld = 10s;

std::filesystem::path generated_eni(const TempDir& dir) {
    ecpair::sim::GeneratedEniOptions options;
    options.slaves = 4;
    options.input_bytes = 4;
    options.output_bytes = 4;
    const auto path = dir / "line.xml";
    std::ofstream(path) << ecpair::sim::generate_eni(options);
    return path;
}

bool all_in_op(const StatusReply& s) {
    return s.master_state() == "OP" && std::all_of(s.slaves().begin(), s.slaves().end(), [](const auto& slave) {
               return slave.present() && slave.al_state() == "OP";
           });
}

std::vector<EventMessage> of_kind(const EventRecorder& events, const std::string& kind) {
    std::vector<EventMessage> out;
    for (const auto& e : events.events()) {
        if (e.kind() == kind) out.push_back(e);
    }
    return out;
}

std::size_t log_lines_with(const std::string& log, const std::string& marker) {
    std::istringstream lines(log);
    std::size_t n = 0;
    for (std::string line; std::getline(lines, line);) {
        if (line.find(marker) != std::string::npos) ++n;
    }
    return n;
}

}  // namespace

TEST_CASE("a WKC fault held for 10 s is logged when it starts, once a second, and when it ends, with its counts",
          "[netns][log]") {
    TempDir dir{"ecpair-log"};
    RingTopology topology(Controllers::Single);
    topology.pull(Cable::RingReturn);  // a line: the last slave turns the frames back
    const auto eni = generated_eni(dir);
    EcsimProcess ecsim(topology.sim(), {eni, "sim-main", std::nullopt, dir.path(), 70});
    EcpairdSettings settings;
    settings.eni = eni;
    settings.dir = dir.path();
    settings.red_if.clear();
    settings.cable_redundancy = false;
    settings.demo = "WALKING_BIT";
    EcpairdProcess daemon(topology.m1(), settings);
    EventRecorder events(daemon.socket());
    const auto op = daemon.wait_for(all_in_op, kReachOp);
    INFO(daemon.log());
    REQUIRE(op);
    const auto wkc_before = op->counters().wkc_errors();

    // Slaves 3 and 4 are cut off: the datagrams they answer come back short, every cycle.
    REQUIRE(ecsim.ctl("break 2").first == 0);
    const auto first = events.wait_for("cyclic-wkc-error", "", 20s);
    INFO(events.dump());
    REQUIRE(first);
    CHECK(first->repeat().empty());
    std::this_thread::sleep_for(kFaultHeld);
    const auto held = of_kind(events, "cyclic-wkc-error");
    // The start and at most one summary a second (the first 1 s after the start).
    CHECK(held.size() <= 1 + 10);
    CHECK(std::count_if(held.begin(), held.end(), [](const auto& e) { return e.repeat() == "summary"; }) >= 8);

    // The cable back; the slaves behind it fell to SAFEOP (their watchdog): start them over.
    REQUIRE(ecsim.ctl("repair 2").first == 0);
    REQUIRE(daemon.request_state("INIT").empty());
    REQUIRE(daemon.wait_for([](const StatusReply& s) { return s.master_state() == "INIT"; }, kReachOp));
    REQUIRE(daemon.request_state("OP").empty());
    const auto back = daemon.wait_for(all_in_op, kReachOp);
    REQUIRE(back);

    // A second without a WKC error ends the fault: the end carries its total.
    const auto end = events.wait_for("cyclic-wkc-error", "ended, none since cycle", 10s);
    REQUIRE(end);
    CHECK(end->repeat() == "end");
    const auto after = daemon.status();
    const auto all = of_kind(events, "cyclic-wkc-error");
    std::uint64_t counted = 0;
    for (const auto& e : all) counted += e.count();
    CHECK(counted == end->total());
    CHECK(end->total() == after.counters().wkc_errors() - wkc_before);
    CHECK(end->first_cycle() == first->cycle());

    // The log: one line per report. From the start to the end (wall time: a loaded machine skips
    // cycles, so cycle numbers undercount it) there is at most one summary a second.
    const double seconds = static_cast<double>(end->unix_time_ms() - first->unix_time_ms()) / 1000.0;
    CHECK(seconds >= 10.0);  // held 10 s, then a quiet second
    const auto lines = log_lines_with(daemon.log(), "event cyclic-wkc-error:");
    CHECK(lines == all.size());
    CHECK(static_cast<double>(lines) <= seconds + 2);  // the start, at most one a second, the end
}
