#include "ecpair/systemd/journal.hpp"

#include <sys/stat.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>

#include <spdlog/pattern_formatter.h>
#include <spdlog/sinks/systemd_sink.h>

#include "ecpair/common/log.hpp"

namespace ecpair::systemd {

bool is_journal_stream(int fd, const char* journal_stream) {
    if (journal_stream == nullptr) return false;
    unsigned long long device = 0;
    unsigned long long inode = 0;
    if (std::sscanf(journal_stream, "%llu:%llu", &device, &inode) != 2) return false;
    struct stat info {};
    if (::fstat(fd, &info) != 0) return false;
    return static_cast<unsigned long long>(info.st_dev) == device && static_cast<unsigned long long>(info.st_ino) == inode;
}

bool log_to_journal_if_connected(const std::string& identifier) {
    if (!is_journal_stream(STDERR_FILENO, std::getenv("JOURNAL_STREAM"))) return false;
    auto sink = std::make_shared<spdlog::sinks::systemd_sink_mt>(identifier, true);
    // The journal stamps time and priority itself: the line keeps the module.
    sink->set_formatter(std::make_unique<spdlog::pattern_formatter>("%n: %v"));
    set_log_sinks({sink});
    return true;
}

}  // namespace ecpair::systemd
