#pragma once
// Network namespaces, veth cables and child processes for tests that need a
// real wire (label `netns`, root required).
//
//   TestNamespace ns;                       // "ecpt-<pid>-<n>", deleted on destruction
//   ns.create_veth("m0", "s0");             // a cable, both ends up
//   {
//       NamespaceScope inside(ns);          // this thread now lives in ns
//       link = PcapLink::open("m0");        // sockets stay bound to ns
//   }                                       // back where we were
//   ChildProcess sim({"ecsim", ...}, log, &ns);  // runs inside ns, killed on destruction
//
// Cleanup happens in destructors, so a failing assertion (an exception)
// still removes everything. Fatal signals (SIGINT, SIGTERM, SIGABRT, SIGSEGV,
// ...) remove the namespaces of the dying process too. Namespaces left over
// by a process that was SIGKILLed are removed by the next TestNamespace with
// the same prefix (their names carry the dead process's pid).
//
// Every helper throws std::runtime_error naming the command that failed.

#include <sys/types.h>

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace ecpair::test {

// Runs a program (argv[0] looked up in PATH), waits for it, and returns its
// exit status (128 + signal number when a signal ended it).
int run_command(const std::vector<std::string>& argv);

class TestNamespace {
public:
    // Creates "<prefix>-<pid>-<n>" with loopback up and IPv6 disabled (so no
    // router solicitations or other frames appear on test cables unasked).
    explicit TestNamespace(std::string_view prefix = "ecpt");
    ~TestNamespace();
    TestNamespace(const TestNamespace&) = delete;
    TestNamespace& operator=(const TestNamespace&) = delete;

    const std::string& name() const { return name_; }
    std::string path() const;  // /run/netns/<name>

    // Runs `sh -c shell_command` inside the namespace; returns its exit status.
    int exec(const std::string& shell_command) const;

    // A veth pair with both ends inside this namespace, both up.
    void create_veth(const std::string& end_a, const std::string& end_b) const;
    // Moves an interface of this namespace into `other` and sets it up there.
    void move_link(const std::string& ifname, const TestNamespace& other) const;
    // `ip link set <ifname> up|down` inside this namespace.
    void set_link(const std::string& ifname, bool up) const;
    // The kernel's count of frames sent on `ifname` and dropped; on a veth
    // that is a frame sent while the other end was down (a pulled cable).
    std::uint64_t tx_dropped(const std::string& ifname) const;

private:
    void ip(std::vector<std::string> arguments) const;  // `ip -n <name> ...`, throws on failure

    std::string name_;
    int cleanup_slot_ = -1;
};

// Moves the calling thread into a namespace; the destructor moves it back.
// Sockets opened meanwhile stay in the namespace after the scope ends.
class NamespaceScope {
public:
    explicit NamespaceScope(const TestNamespace& target);
    ~NamespaceScope();
    NamespaceScope(const NamespaceScope&) = delete;
    NamespaceScope& operator=(const NamespaceScope&) = delete;

private:
    int original_;  // fd of the thread's namespace before the scope
};

// How long a program the tests start (ecsim, ecpaird, ecpairctl) may take to
// come up or answer before the test calls it a hang.
inline constexpr std::chrono::seconds kProgramStartGuard{10};

// A program running in the background, with stdout and stderr written to a
// log file. Inside a namespace it is started through `ip netns exec` (which
// also gives it the namespace's view of /sys). It runs in its own process
// group, gets SIGKILL if the test process dies, and is stopped and reaped on
// destruction.
class ChildProcess {
public:
    ChildProcess(std::vector<std::string> argv, std::filesystem::path log_file, const TestNamespace* inside = nullptr);
    ~ChildProcess();
    ChildProcess(const ChildProcess&) = delete;
    ChildProcess& operator=(const ChildProcess&) = delete;

    pid_t pid() const { return pid_; }
    const std::filesystem::path& log_file() const { return log_file_; }
    std::string log() const;  // what the process wrote so far

    // True until the process has exited.
    bool running();
    // Waits up to `timeout` for the process to exit; its exit status, or
    // nullopt while it still runs.
    std::optional<int> wait_for_exit(std::chrono::milliseconds timeout);
    // SIGTERM to the process group, SIGKILL after `grace`; returns the exit status.
    int stop(std::chrono::milliseconds grace = std::chrono::seconds(2));

private:
    bool reap();  // collects the exit status if the process has exited

    std::filesystem::path log_file_;
    pid_t pid_ = -1;
    int pidfd_ = -1;  // readable once the process has exited
    std::optional<int> exit_status_;
};

}  // namespace ecpair::test
