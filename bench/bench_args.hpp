#pragma once
// Positional whole-number arguments of the benchmarks that take them
// (`bench RUNS HANGS SECONDS`): a word that is not a positive number is
// refused with the usage line, not a crash.

#include <charconv>
#include <cstdio>
#include <cstdlib>
#include <string_view>

namespace ecpair::bench {

// argv[index] as a positive int, `fallback` when absent; exits with status 2
// and `usage` when it is not one.
inline int positional_count(int argc, char** argv, int index, int fallback, const char* usage) {
    if (argc <= index) return fallback;
    const std::string_view word = argv[index];
    int value = 0;
    const auto [end, error] = std::from_chars(word.data(), word.data() + word.size(), value);
    if (error != std::errc{} || end != word.data() + word.size() || value <= 0) {
        std::fprintf(stderr, "%s: argument %d ('%s') is not a positive number\nusage: %s\n", argv[0], index, argv[index],
                     usage);
        std::exit(2);
    }
    return value;
}

}  // namespace ecpair::bench
