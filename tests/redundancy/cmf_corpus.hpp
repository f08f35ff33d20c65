#pragma once
// The seed corpus of fuzz_cmf_assembler, made from real CmfWriter output.
// A fuzz input is: one byte choosing the assembler's layout (bit 0: 0 the
// small layout, 1 the large one), then frames, each as a 2-byte
// little-endian length followed by that many bytes. make_cmf_corpus writes
// these entries to a directory; cmf_corpus_tests checks that the committed
// files still equal them, which also pins the wire format of version 1.

#include <cstdint>
#include <string>
#include <vector>

#include "ecpair/redundancy/cmf_format.hpp"

namespace ecpair::test {

struct CorpusEntry {
    std::string name;
    std::vector<std::uint8_t> bytes;
};

// The layout a fuzz input's first byte selects.
redundancy::CmfLayout fuzz_layout(std::uint8_t selector);

std::vector<CorpusEntry> make_cmf_corpus();

}  // namespace ecpair::test
