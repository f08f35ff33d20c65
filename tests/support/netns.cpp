// Test namespaces are made and removed with iproute2 (`ip netns add/del`),
// which the lead's scripts and a reader already know; only entering a
// namespace (setns) and the signal-time cleanup are done with system calls.
//
// Signal-time cleanup: `ip netns del` is a bind mount at /run/netns/<name>
// being detached and the file unlinked; once nothing refers to the namespace
// the kernel destroys it with its interfaces. umount2() and unlink() are
// async-signal-safe, so a fatal-signal handler can do the same for every live
// TestNamespace (kept in a fixed table of paths), then re-raises the signal
// with the handler that was there before (Catch2's, or the default).

#include "netns.hpp"

#include <dirent.h>
#include <fcntl.h>
#include <poll.h>
#include <pthread.h>
#include <sched.h>
#include <signal.h>
#include <spawn.h>
#include <sys/mount.h>
#include <sys/prctl.h>
#include <sys/syscall.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <atomic>
#include <cerrno>
#include <charconv>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <mutex>
#include <set>
#include <sstream>
#include <stdexcept>
#include <system_error>

extern char** environ;

namespace ecpair::test {
namespace {

// ---- removal of namespaces on fatal signals ------------------------------------

constexpr std::size_t kCleanupSlots = 64;
constexpr std::size_t kPathCapacity = 128;

enum SlotState : int { kFree = 0, kClaiming = 1, kActive = 2 };

struct CleanupSlot {
    std::atomic<int> state{kFree};
    std::array<char, kPathCapacity> path{};
};

std::array<CleanupSlot, kCleanupSlots> cleanup_slots;

constexpr std::array kFatalSignals{SIGHUP, SIGINT, SIGQUIT, SIGTERM, SIGABRT, SIGSEGV, SIGBUS, SIGFPE, SIGILL};
std::array<struct sigaction, kFatalSignals.size()> previous_actions;

void remove_namespaces_on_signal(int signal_number) {
    for (auto& slot : cleanup_slots) {
        if (slot.state.load(std::memory_order_acquire) != kActive) continue;
        ::umount2(slot.path.data(), MNT_DETACH);
        ::unlink(slot.path.data());
        slot.state.store(kFree, std::memory_order_release);
    }
    for (std::size_t i = 0; i < kFatalSignals.size(); ++i) {
        if (kFatalSignals[i] == signal_number) ::sigaction(signal_number, &previous_actions[i], nullptr);
    }
    ::raise(signal_number);
}

// Installed before main() (so before Catch2 installs its own handlers, which
// hand the signal back to this one after reporting).
const bool signal_handlers_installed = [] {
    struct sigaction action {};
    action.sa_handler = remove_namespaces_on_signal;
    sigemptyset(&action.sa_mask);
    for (std::size_t i = 0; i < kFatalSignals.size(); ++i) ::sigaction(kFatalSignals[i], &action, &previous_actions[i]);
    return true;
}();

int claim_cleanup_slot(const std::string& path) {
    if (path.size() >= kPathCapacity) return -1;
    for (std::size_t i = 0; i < cleanup_slots.size(); ++i) {
        int expected = kFree;
        if (!cleanup_slots[i].state.compare_exchange_strong(expected, kClaiming)) continue;
        std::memcpy(cleanup_slots[i].path.data(), path.c_str(), path.size() + 1);
        cleanup_slots[i].state.store(kActive, std::memory_order_release);
        return static_cast<int>(i);
    }
    return -1;
}

void release_cleanup_slot(int slot) {
    if (slot >= 0) cleanup_slots[static_cast<std::size_t>(slot)].state.store(kFree, std::memory_order_release);
}

// ---- commands ------------------------------------------------------------------

std::string join(const std::vector<std::string>& argv) {
    std::string text;
    for (const auto& argument : argv) {
        if (!text.empty()) text += ' ';
        text += argument;
    }
    return text;
}

void run_or_throw(const std::vector<std::string>& argv) {
    if (const int status = run_command(argv); status != 0) {
        throw std::runtime_error("'" + join(argv) + "' failed with exit status " + std::to_string(status));
    }
}

int exit_status_of(int wait_status) {
    if (WIFEXITED(wait_status)) return WEXITSTATUS(wait_status);
    if (WIFSIGNALED(wait_status)) return 128 + WTERMSIG(wait_status);
    return -1;
}

std::vector<char*> c_arguments(const std::vector<std::string>& argv) {
    std::vector<char*> pointers;
    for (const auto& argument : argv) pointers.push_back(const_cast<char*>(argument.c_str()));
    pointers.push_back(nullptr);
    return pointers;
}

constexpr const char* kNamespaceDirectory = "/run/netns";

// Removes "<prefix>-<pid>-<n>" namespaces whose process no longer exists
// (left behind by a test run that was killed with SIGKILL).
void remove_stale_namespaces(std::string_view prefix) {
    DIR* directory = ::opendir(kNamespaceDirectory);
    if (directory == nullptr) return;
    std::vector<std::string> stale;
    while (const dirent* entry = ::readdir(directory)) {
        const std::string_view name(entry->d_name);
        if (name.size() <= prefix.size() + 1 || !name.starts_with(prefix) || name[prefix.size()] != '-') continue;
        const std::string_view rest = name.substr(prefix.size() + 1);
        pid_t owner = 0;
        const auto [end, error] = std::from_chars(rest.data(), rest.data() + rest.size(), owner);
        if (error != std::errc() || end == rest.data() + rest.size() || *end != '-') continue;
        if (owner != ::getpid() && ::kill(owner, 0) != 0 && errno == ESRCH) stale.emplace_back(name);
    }
    ::closedir(directory);
    for (const auto& name : stale) {
        std::fprintf(stderr, "netns: removing stale test namespace %s\n", name.c_str());
        run_command({"ip", "netns", "del", name});
    }
}

}  // namespace

int run_command(const std::vector<std::string>& argv) {
    auto arguments = c_arguments(argv);
    pid_t pid = 0;
    if (const int error = ::posix_spawnp(&pid, arguments[0], nullptr, nullptr, arguments.data(), environ); error != 0) {
        throw std::system_error(error, std::system_category(), "cannot start '" + join(argv) + "'");
    }
    int status = 0;
    while (::waitpid(pid, &status, 0) < 0) {
        if (errno != EINTR) throw std::system_error(errno, std::system_category(), "waitpid for '" + join(argv) + "'");
    }
    return exit_status_of(status);
}

// ---- TestNamespace -------------------------------------------------------------

TestNamespace::TestNamespace(std::string_view prefix) {
    static std::atomic<int> counter{0};
    static std::mutex swept_mutex;
    static std::set<std::string, std::less<>> swept_prefixes;
    {
        std::lock_guard lock(swept_mutex);
        if (swept_prefixes.emplace(prefix).second) remove_stale_namespaces(prefix);
    }

    name_ = std::string(prefix) + "-" + std::to_string(::getpid()) + "-" + std::to_string(counter++);
    run_or_throw({"ip", "netns", "add", name_});
    cleanup_slot_ = claim_cleanup_slot(path());
    try {
        ip({"link", "set", "lo", "up"});
        const int ipv6_off = exec(
            "[ ! -d /proc/sys/net/ipv6 ] || { echo 1 > /proc/sys/net/ipv6/conf/all/disable_ipv6 && "
            "echo 1 > /proc/sys/net/ipv6/conf/default/disable_ipv6; }");
        if (ipv6_off != 0) throw std::runtime_error("cannot disable IPv6 in namespace " + name_);
    } catch (...) {
        run_command({"ip", "netns", "del", name_});
        release_cleanup_slot(cleanup_slot_);
        throw;
    }
}

TestNamespace::~TestNamespace() {
    try {
        if (run_command({"ip", "netns", "del", name_}) != 0) {
            std::fprintf(stderr, "netns: could not delete namespace %s\n", name_.c_str());
        }
    } catch (const std::exception& error) {
        std::fprintf(stderr, "netns: could not delete namespace %s: %s\n", name_.c_str(), error.what());
    }
    release_cleanup_slot(cleanup_slot_);
}

std::string TestNamespace::path() const { return std::string(kNamespaceDirectory) + "/" + name_; }

int TestNamespace::exec(const std::string& shell_command) const {
    return run_command({"ip", "netns", "exec", name_, "sh", "-c", shell_command});
}

std::uint64_t TestNamespace::tx_dropped(const std::string& ifname) const {
    // /sys shows the namespace it was mounted in; `ip netns exec` mounts this one's.
    const std::string command = "ip netns exec " + name_ + " cat /sys/class/net/" + ifname + "/statistics/tx_dropped";
    FILE* pipe = ::popen(command.c_str(), "r");
    if (pipe == nullptr) throw std::runtime_error("cannot run: " + command);
    unsigned long long value = 0;
    const int fields = std::fscanf(pipe, "%llu", &value);
    const int status = ::pclose(pipe);
    if (fields != 1 || status != 0) throw std::runtime_error("no tx_dropped counter from: " + command);
    return value;
}

void TestNamespace::create_veth(const std::string& end_a, const std::string& end_b) const {
    ip({"link", "add", end_a, "type", "veth", "peer", "name", end_b});
    set_link(end_a, true);
    set_link(end_b, true);
}

void TestNamespace::move_link(const std::string& ifname, const TestNamespace& other) const {
    ip({"link", "set", ifname, "netns", other.name()});
    other.set_link(ifname, true);
}

void TestNamespace::set_link(const std::string& ifname, bool up) const {
    ip({"link", "set", ifname, up ? "up" : "down"});
}

void TestNamespace::ip(std::vector<std::string> arguments) const {
    std::vector<std::string> argv{"ip", "-n", name_};
    argv.insert(argv.end(), arguments.begin(), arguments.end());
    run_or_throw(argv);
}

// ---- NamespaceScope ------------------------------------------------------------

NamespaceScope::NamespaceScope(const TestNamespace& target)
    : original_(::open("/proc/thread-self/ns/net", O_RDONLY | O_CLOEXEC)) {
    if (original_ < 0) throw std::system_error(errno, std::system_category(), "open /proc/thread-self/ns/net");
    const int target_fd = ::open(target.path().c_str(), O_RDONLY | O_CLOEXEC);
    if (target_fd < 0 || ::setns(target_fd, CLONE_NEWNET) != 0) {
        const int error = errno;
        if (target_fd >= 0) ::close(target_fd);
        ::close(original_);
        throw std::system_error(error, std::system_category(), "cannot enter network namespace " + target.name());
    }
    ::close(target_fd);
}

NamespaceScope::~NamespaceScope() {
    if (::setns(original_, CLONE_NEWNET) != 0) {
        // Carrying on would run the rest of the test in the wrong namespace.
        std::perror("netns: cannot return to the original network namespace");
        std::abort();
    }
    ::close(original_);
}

// ---- ChildProcess --------------------------------------------------------------

ChildProcess::ChildProcess(std::vector<std::string> argv, std::filesystem::path log_file, const TestNamespace* inside)
    : log_file_(std::move(log_file)) {
    if (argv.empty()) throw std::invalid_argument("ChildProcess needs a program to run");
    if (inside != nullptr) argv.insert(argv.begin(), {"ip", "netns", "exec", inside->name()});
    auto arguments = c_arguments(argv);  // prepared before fork: the child only makes system calls

    const int log_fd = ::open(log_file_.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    if (log_fd < 0) throw std::system_error(errno, std::system_category(), "cannot create log " + log_file_.string());
    int exec_status[2];  // the child reports a failed exec's errno here; EOF means exec worked
    if (::pipe2(exec_status, O_CLOEXEC) != 0) {
        ::close(log_fd);
        throw std::system_error(errno, std::system_category(), "pipe");
    }
    // The child must not run this process's fatal-signal handler (it would
    // remove our namespaces): signals stay blocked until it has reset them.
    sigset_t all_signals;
    sigset_t previous_mask;
    sigfillset(&all_signals);
    ::pthread_sigmask(SIG_BLOCK, &all_signals, &previous_mask);
    const pid_t parent = ::getpid();
    pid_ = ::fork();
    if (pid_ == 0) {
        for (const int signal_number : kFatalSignals) ::signal(signal_number, SIG_DFL);
        ::pthread_sigmask(SIG_SETMASK, &previous_mask, nullptr);
        ::setpgid(0, 0);
        ::prctl(PR_SET_PDEATHSIG, SIGKILL);
        if (::getppid() != parent) ::_exit(127);
        const int null_fd = ::open("/dev/null", O_RDONLY);
        ::dup2(null_fd, STDIN_FILENO);
        ::dup2(log_fd, STDOUT_FILENO);
        ::dup2(log_fd, STDERR_FILENO);
        ::execvp(arguments[0], arguments.data());
        const int error = errno;
        [[maybe_unused]] const auto written = ::write(exec_status[1], &error, sizeof(error));
        ::_exit(127);
    }
    const int fork_error = errno;
    ::pthread_sigmask(SIG_SETMASK, &previous_mask, nullptr);
    ::close(log_fd);
    ::close(exec_status[1]);
    if (pid_ < 0) {
        ::close(exec_status[0]);
        throw std::system_error(fork_error, std::system_category(), "fork for '" + join(argv) + "'");
    }
    ::setpgid(pid_, pid_);  // also here, so that stop() never races the child's own setpgid
    int exec_error = 0;
    ssize_t got = 0;
    do {
        got = ::read(exec_status[0], &exec_error, sizeof(exec_error));
    } while (got < 0 && errno == EINTR);
    ::close(exec_status[0]);
    if (got > 0) {
        ::waitpid(pid_, nullptr, 0);
        throw std::system_error(exec_error, std::system_category(), "cannot run '" + join(argv) + "'");
    }
    // (glibc 2.36's <sys/pidfd.h> lacks C linkage for C++, hence the raw call.)
    pidfd_ = static_cast<int>(::syscall(SYS_pidfd_open, pid_, 0));
    if (pidfd_ < 0) {
        const int error = errno;
        stop();
        throw std::system_error(error, std::system_category(), "pidfd_open");
    }
}

ChildProcess::~ChildProcess() {
    stop();
    if (pidfd_ >= 0) ::close(pidfd_);
}

std::string ChildProcess::log() const {
    std::ifstream in(log_file_);
    std::stringstream text;
    text << in.rdbuf();
    return text.str();
}

bool ChildProcess::reap() {
    if (exit_status_) return true;
    int status = 0;
    if (::waitpid(pid_, &status, WNOHANG) != pid_) return false;
    exit_status_ = exit_status_of(status);
    return true;
}

bool ChildProcess::running() { return !reap(); }

std::optional<int> ChildProcess::wait_for_exit(std::chrono::milliseconds timeout) {
    if (!reap() && pidfd_ >= 0) {
        pollfd exited{pidfd_, POLLIN, 0};
        while (::poll(&exited, 1, static_cast<int>(timeout.count())) < 0 && errno == EINTR) {
        }
        reap();
    }
    return exit_status_;
}

int ChildProcess::stop(std::chrono::milliseconds grace) {
    if (reap()) return *exit_status_;
    ::kill(-pid_, SIGTERM);
    if (!wait_for_exit(grace)) {
        ::kill(-pid_, SIGKILL);
        int status = 0;
        while (::waitpid(pid_, &status, 0) < 0 && errno == EINTR) {
        }
        exit_status_ = exit_status_of(status);
    }
    return *exit_status_;
}

}  // namespace ecpair::test
