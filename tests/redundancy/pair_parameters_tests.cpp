// PairParameters: the byte-exact encoding, a fingerprint fixed for all
// builds (a known vector computed outside this code), and the names of
// what differs between two masters.

#include <catch2/catch.hpp>

#include <array>
#include <set>
#include <string>
#include <vector>

#include "cmf_test_support.hpp"
#include "ecpair/common/hex.hpp"
#include "ecpair/redundancy/pair_parameters.hpp"

using ecpair::redundancy::differences;
using ecpair::redundancy::PairParameters;

TEST_CASE("pair parameters encode byte by byte as WIRE_FORMAT.md says", "[redundancy][pair]") {
    std::array<std::uint8_t, PairParameters::kEncodedSize> bytes{};
    ecpair::test::test_parameters().encode(bytes);
    CHECK(ecpair::to_hex(bytes) == "efcdab896745230140420f0000000000100000000800000002000500");
    CHECK(PairParameters::decode(bytes) == ecpair::test::test_parameters());
}

TEST_CASE("the fingerprint is FNV-1a 64 over the encoding (known vector)", "[redundancy][pair]") {
    // Computed independently (Python) over efcdab89...000500.
    CHECK(ecpair::test::test_parameters().fingerprint() == 0x0b7879f76ca94f4full);
}

TEST_CASE("every parameter changes the fingerprint", "[redundancy][pair]") {
    const PairParameters base = ecpair::test::test_parameters();
    std::vector<PairParameters> variants(9, base);
    variants[0].eni_content_hash ^= 1;
    variants[1].cycle_time = std::chrono::microseconds(500);
    variants[2].cable_redundancy = !base.cable_redundancy;
    variants[3].split_lrw = !base.split_lrw;
    variants[4].master_pd_out_size += 1;
    variants[5].master_pd_in_size += 1;
    variants[6].update_slave_pd_in = !base.update_slave_pd_in;
    variants[7].update_slave_pd_out = !base.update_slave_pd_out;
    variants[8].max_acyc_frames_per_cycle += 1;
    std::set<std::uint64_t> fingerprints{base.fingerprint()};
    for (const auto& v : variants) {
        CHECK(differences(base, v).size() == 1);
        fingerprints.insert(v.fingerprint());
    }
    CHECK(fingerprints.size() == variants.size() + 1);
}

TEST_CASE("differences name each differing parameter, ours first", "[redundancy][pair]") {
    const PairParameters ours = ecpair::test::test_parameters();
    CHECK(differences(ours, ours).empty());

    PairParameters theirs = ours;
    theirs.eni_content_hash = 0x1111;
    theirs.cycle_time = std::chrono::nanoseconds(62'500);
    theirs.split_lrw = true;
    theirs.master_pd_in_size = 32;
    theirs.update_slave_pd_out = true;
    theirs.max_acyc_frames_per_cycle = 4;
    CHECK(differences(ours, theirs) == std::vector<std::string>{
                                           "ENI (content hash 0x0123456789abcdef vs 0x0000000000001111)",
                                           "cycle time 1000 µs vs 62.5 µs",
                                           "split LRW off vs on",
                                           "master PD in size 8 vs 32 bytes",
                                           "update slave PD out off vs on",
                                           "max acyclic frames per cycle 2 vs 4",
                                       });

    PairParameters other = ours;
    other.cable_redundancy = false;
    other.master_pd_out_size = 0;
    other.update_slave_pd_in = false;
    CHECK(differences(ours, other) == std::vector<std::string>{"cable redundancy on vs off",
                                                               "master PD out size 16 vs 0 bytes",
                                                               "update slave PD in on vs off"});
}
