#pragma once
// A directory for one test's files (logs, sockets, captures), removed with
// everything in it when the test ends - unless ECPAIR_TEST_KEEP is set in
// the environment (to read a failed test's logs afterwards).

#include <unistd.h>

#include <atomic>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <string_view>

namespace ecpair::test {

class TempDir {
public:
    explicit TempDir(std::string_view prefix = "ecpair-test") {
        static std::atomic<int> counter{0};
        path_ = std::filesystem::temp_directory_path() /
                (std::string(prefix) + "-" + std::to_string(::getpid()) + "-" + std::to_string(counter++));
        std::filesystem::create_directories(path_);
    }
    ~TempDir() {
        if (std::getenv("ECPAIR_TEST_KEEP") != nullptr) return;
        std::error_code ignored;
        std::filesystem::remove_all(path_, ignored);
    }
    TempDir(const TempDir&) = delete;
    TempDir& operator=(const TempDir&) = delete;

    const std::filesystem::path& path() const { return path_; }
    std::filesystem::path operator/(std::string_view name) const { return path_ / name; }

private:
    std::filesystem::path path_;
};

}  // namespace ecpair::test
