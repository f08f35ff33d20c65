#pragma once
// Paths of the ENI test files and a loader that fails the test with the
// loader's own message when a file that must load does not.

#include <memory>
#include <string>

#include <catch2/catch.hpp>
#include <fmt/format.h>

#include "ecpair/eni/loader.hpp"

namespace ecpair::eni::test {

// (fmt::format, not std::string + "...": GCC 12 reports a false -Warray-bounds in that.)
inline std::string real_eni(const std::string& name) { return fmt::format("{}/{}", ECPAIR_TEST_ENI_DIR, name); }

inline std::string extra_eni(const std::string& name) {
    return fmt::format("{}/eni_extra/{}", ECPAIR_TEST_DATA_DIR, name);
}

inline std::string bad_eni(const std::string& name) { return fmt::format("{}/eni_bad/{}", ECPAIR_TEST_DATA_DIR, name); }

inline std::shared_ptr<const EniConfig> must_load(const std::string& path) {
    auto result = load_eni_file(path);
    INFO((result ? std::string("loaded") : result.error().describe()));
    REQUIRE(result.has_value());
    return *result;
}

}  // namespace ecpair::eni::test
