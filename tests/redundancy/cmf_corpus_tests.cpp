// The committed seed corpus of fuzz_cmf_assembler is what CmfWriter writes
// today: a change to the bytes of format version 1 shows up here. And each
// seed does what its name says when replayed.

#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>

#include "cmf_corpus.hpp"
#include "cmf_test_support.hpp"
#include "ecpair/redundancy/cmf_assembler.hpp"

using namespace ecpair;
using namespace ecpair::redundancy;

namespace {

std::vector<std::uint8_t> read_file(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

struct Replay {
    std::size_t completed = 0;
    std::vector<CmfErrc> errors;
};

Replay replay(const std::vector<std::uint8_t>& input) {
    CmfAssembler assembler(CmfPlan::make(test::fuzz_layout(input[0])).value());
    Replay result;
    std::size_t at = 1;
    while (at + 2 <= input.size()) {
        const std::size_t length = load_le<std::uint16_t>(input, at);
        at += 2;
        for (const auto& r : test::feed_frame(assembler, ConstBytes(input).subspan(at, length))) {
            if (!r) result.errors.push_back(r.error().code);
            else if (*r == CmfAssembler::Outcome::Completed) ++result.completed;
        }
        at += length;
    }
    return result;
}

}  // namespace

TEST_CASE("the committed CMF corpus is what the writer writes", "[redundancy][cmf][corpus]") {
    const std::filesystem::path dir(CMF_CORPUS_DIR);
    for (const auto& entry : test::make_cmf_corpus()) {
        INFO(entry.name);
        CHECK(read_file(dir / entry.name) == entry.bytes);
    }
}

TEST_CASE("the corpus seeds replay as their names say", "[redundancy][cmf][corpus]") {
    std::map<std::string, Replay> replays;
    for (const auto& entry : test::make_cmf_corpus()) replays[entry.name] = replay(entry.bytes);
    CHECK(replays.at("small_one_cycle").completed == 1);
    CHECK(replays.at("large_one_cycle").completed == 1);
    CHECK(replays.at("large_processed_copies").completed == 1);
    CHECK(replays.at("large_cycles_out_of_order").completed == 2);  // 5 and 6; 4 is stale
    CHECK(replays.at("small_partner_differs").completed == 0);
    CHECK(replays.at("small_partner_differs").errors.front() == CmfErrc::PartnerDiffers);
    for (const auto& name : {"small_one_cycle", "large_one_cycle", "large_processed_copies", "large_cycles_out_of_order"}) {
        CHECK(replays.at(name).errors.empty());
    }
}
