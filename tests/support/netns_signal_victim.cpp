// Helper of support_netns_tests: creates a TestNamespace, prints its path,
// and dies of the signal named on the command line (SIGTERM, SIGABRT or
// SIGSEGV), so the test can check that the namespace went with it.

#include <signal.h>

#include <cstdio>
#include <string_view>

#include "netns.hpp"

int main(int argc, char** argv) {
    const std::string_view name = argc > 1 ? argv[1] : "SIGTERM";
    const int signal_number = name == "SIGABRT" ? SIGABRT : name == "SIGSEGV" ? SIGSEGV : SIGTERM;
    ecpair::test::TestNamespace doomed;
    std::printf("%s\n", doomed.path().c_str());
    std::fflush(stdout);
    ::raise(signal_number);
    return 0;
}
