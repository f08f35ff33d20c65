// Runs a libFuzzer target without libFuzzer: replays every file of a corpus
// directory, then applies a fixed number of seeded random mutations to corpus
// entries (bit flips, byte changes, truncation, insertion, splicing). The
// seed is fixed so a failure reproduces; the iteration count is the second
// argument. A crash or sanitizer report fails the ctest.

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <string>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size);

namespace {

using Input = std::vector<std::uint8_t>;

std::vector<Input> load_corpus(const std::filesystem::path& dir) {
    std::vector<Input> corpus;
    if (!std::filesystem::is_directory(dir)) return corpus;
    std::vector<std::filesystem::path> files;
    for (const auto& entry : std::filesystem::recursive_directory_iterator(dir)) {
        if (entry.is_regular_file()) files.push_back(entry.path());
    }
    std::sort(files.begin(), files.end());
    for (const auto& file : files) {
        std::ifstream in(file, std::ios::binary);
        corpus.emplace_back(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    }
    return corpus;
}

void mutate(Input& input, const std::vector<Input>& corpus, std::mt19937_64& rng) {
    auto pick = [&](std::size_t n) { return n == 0 ? 0 : static_cast<std::size_t>(rng() % n); };
    const int rounds = 1 + static_cast<int>(pick(4));
    for (int r = 0; r < rounds; ++r) {
        switch (pick(6)) {
            case 0:  // flip a bit
                if (!input.empty()) input[pick(input.size())] ^= static_cast<std::uint8_t>(1u << pick(8));
                break;
            case 1:  // set a byte to an interesting value
                if (!input.empty()) {
                    static constexpr std::uint8_t kValues[] = {0x00, 0x01, 0x7f, 0x80, 0xff, 0x3c, 0x22};
                    input[pick(input.size())] = kValues[pick(std::size(kValues))];
                }
                break;
            case 2:  // truncate
                input.resize(pick(input.size() + 1));
                break;
            case 3:  // insert random bytes
            {
                const std::size_t at = pick(input.size() + 1);
                const std::size_t n = 1 + pick(8);
                for (std::size_t i = 0; i < n; ++i) {
                    input.insert(input.begin() + static_cast<std::ptrdiff_t>(at), static_cast<std::uint8_t>(rng()));
                }
                break;
            }
            case 4:  // erase a range
                if (!input.empty()) {
                    const std::size_t at = pick(input.size());
                    const std::size_t n = 1 + pick(std::min<std::size_t>(16, input.size() - at));
                    input.erase(input.begin() + static_cast<std::ptrdiff_t>(at),
                                input.begin() + static_cast<std::ptrdiff_t>(std::min(input.size(), at + n)));
                }
                break;
            default:  // splice with another corpus entry
                if (!corpus.empty()) {
                    const Input& other = corpus[pick(corpus.size())];
                    const std::size_t cut = pick(input.size() + 1);
                    const std::size_t from = pick(other.size() + 1);
                    input.resize(cut);
                    input.insert(input.end(), other.begin() + static_cast<std::ptrdiff_t>(from), other.end());
                }
                break;
        }
    }
}

}  // namespace

int main(int argc, char** argv) {
    if (argc < 2) {
        std::fprintf(stderr, "usage: %s CORPUS_DIR [ITERATIONS]\n", argv[0]);
        return 2;
    }
    const auto corpus = load_corpus(argv[1]);
    const long iterations = argc > 2 ? std::strtol(argv[2], nullptr, 10) : 10000;

    for (const auto& input : corpus) LLVMFuzzerTestOneInput(input.data(), input.size());
    LLVMFuzzerTestOneInput(nullptr, 0);

    std::mt19937_64 rng(0xEC0A1Full);
    for (long i = 0; i < iterations; ++i) {
        Input input = corpus.empty() ? Input{} : corpus[static_cast<std::size_t>(rng() % corpus.size())];
        mutate(input, corpus, rng);
        LLVMFuzzerTestOneInput(input.data(), input.size());
    }
    std::fprintf(stderr, "fuzz replay: %zu corpus inputs, %ld mutations, no crash\n", corpus.size(), iterations);
    return 0;
}
