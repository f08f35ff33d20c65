// The netns helpers themselves: namespaces appear and disappear (also when
// the process dies of a signal), NamespaceScope really moves the thread,
// child processes run inside, log, and are stopped and reaped.

#include <net/if.h>
#include <signal.h>
#include <unistd.h>

#include <catch2/catch.hpp>
#include <filesystem>

#include "netns.hpp"

using ecpair::test::ChildProcess;
using ecpair::test::NamespaceScope;
using ecpair::test::TestNamespace;

namespace {

std::filesystem::path log_path(const std::string& name) {
    return std::filesystem::path(ECPAIR_BINARY_DIR) / (name + "-" + std::to_string(::getpid()) + ".log");
}

}  // namespace

TEST_CASE("a test namespace exists while the object lives and is removed afterwards", "[netns]") {
    std::string path;
    {
        TestNamespace first;
        TestNamespace second;
        CHECK(first.name() != second.name());
        path = first.path();
        CHECK(std::filesystem::exists(path));
        CHECK(first.exec("ip link show lo | grep -q LOOPBACK,UP") == 0);
    }
    CHECK_FALSE(std::filesystem::exists(path));
}

TEST_CASE("veth ends live in the namespace and follow set_link", "[netns]") {
    TestNamespace ns;
    ns.create_veth("tva", "tvb");
    CHECK(ns.exec("ip link show tva | grep -q 'state UP'") == 0);
    ns.set_link("tva", false);
    CHECK(ns.exec("ip link show tva | grep -q 'state DOWN'") == 0);
    CHECK(::if_nametoindex("tva") == 0);  // not in the namespace of the test process
}

TEST_CASE("NamespaceScope moves the calling thread in and back out", "[netns]") {
    TestNamespace ns;
    ns.create_veth("tva", "tvb");
    {
        NamespaceScope inside(ns);
        CHECK(::if_nametoindex("tva") != 0);
    }
    CHECK(::if_nametoindex("tva") == 0);
}

TEST_CASE("move_link hands an interface to another namespace, up", "[netns]") {
    TestNamespace left;
    TestNamespace right;
    left.create_veth("tva", "tvb");
    left.move_link("tvb", right);
    CHECK(left.exec("ip link show tvb 2> /dev/null") != 0);
    CHECK(right.exec("ip link show tvb | grep -q ',UP'") == 0);
}

TEST_CASE("a child process runs inside the namespace and writes its log", "[netns]") {
    TestNamespace ns;
    ns.create_veth("tva", "tvb");
    ChildProcess child({"sh", "-c", "ip link show tva > /dev/null && echo inside"}, log_path("child"), &ns);
    CHECK(child.wait_for_exit(std::chrono::seconds(30)) == 0);
    CHECK_FALSE(child.running());
    CHECK(child.log() == "inside\n");
    std::filesystem::remove(child.log_file());
}

TEST_CASE("stop() ends a running child with SIGTERM and reaps it", "[netns]") {
    ChildProcess child({"sleep", "600"}, log_path("sleeper"));
    CHECK(child.running());
    CHECK_FALSE(child.wait_for_exit(std::chrono::milliseconds(0)).has_value());
    CHECK(child.stop() == 128 + SIGTERM);
    CHECK_FALSE(child.running());
    CHECK(::kill(child.pid(), 0) != 0);  // reaped: the pid is gone
    std::filesystem::remove(child.log_file());
}

TEST_CASE("a child's exit status is reported", "[netns]") {
    ChildProcess child({"sh", "-c", "echo to-stderr >&2; exit 3"}, log_path("exit"));
    CHECK(child.wait_for_exit(std::chrono::seconds(30)) == 3);
    CHECK(child.log() == "to-stderr\n");
    std::filesystem::remove(child.log_file());
}

TEST_CASE("a child that cannot be started is an error naming it", "[netns]") {
    try {
        ChildProcess child({"/nonexistent/ecpair-no-such-binary"}, log_path("missing"));
        FAIL("no exception");
    } catch (const std::system_error& error) {
        CHECK(std::string(error.what()).find("ecpair-no-such-binary") != std::string::npos);
    }
    std::filesystem::remove(log_path("missing"));
}

TEST_CASE("a process killed by a fatal signal removes its namespaces", "[netns]") {
    // The victim creates a namespace, prints its path and raises SIGTERM.
    ChildProcess victim({std::string(ECPAIR_BINARY_DIR "/tests/support/netns_signal_victim"), "SIGTERM"},
                        log_path("victim"));
    REQUIRE(victim.wait_for_exit(std::chrono::seconds(30)) == 128 + SIGTERM);
    const std::string output = victim.log();
    const std::string path = output.substr(0, output.find('\n'));
    REQUIRE(path.starts_with("/run/netns/ecpt-"));
    CHECK_FALSE(std::filesystem::exists(path));
    std::filesystem::remove(victim.log_file());
}
