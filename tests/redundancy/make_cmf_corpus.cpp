// Writes the seed corpus of fuzz_cmf_assembler (cmf_corpus.hpp) into a
// directory. Run by hand when the CMF format changes, then commit the files:
//   make_cmf_corpus tests/redundancy/fuzz_corpus/cmf_assembler

#include <cstdio>
#include <filesystem>
#include <fstream>

#include "cmf_corpus.hpp"

int main(int argc, char** argv) {
    if (argc != 2) {
        std::fprintf(stderr, "usage: %s DIRECTORY\n", argv[0]);
        return 2;
    }
    const std::filesystem::path dir(argv[1]);
    std::filesystem::create_directories(dir);
    for (const auto& entry : ecpair::test::make_cmf_corpus()) {
        std::ofstream out(dir / entry.name, std::ios::binary);
        out.write(reinterpret_cast<const char*>(entry.bytes.data()), static_cast<std::streamsize>(entry.bytes.size()));
        if (!out) {
            std::fprintf(stderr, "cannot write %s\n", (dir / entry.name).c_str());
            return 1;
        }
    }
    return 0;
}
