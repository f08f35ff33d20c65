#pragma once
// The link guard program's loop: waits (poll, no busy loop) on the socket
// to ecpaird until a message, end-of-file or the GuardLogic's deadline, and
// executes what the logic decides with a LinkAdmin.

#include <memory>
#include <string>

#include "ecpair/link/link_admin.hpp"
#include "ecpair/linkguard/guard_logic.hpp"

namespace ecpair::linkguard {

struct GuardInterfaces {
    std::string main;
    std::string red;  // empty: no RED adapter
    std::string describe() const;  // "MAIN m1-main, RED m1-red"
};

// Sets both links up or down; the result names what failed.
LinkResult set_links(link::LinkAdmin& admin, const GuardInterfaces& interfaces, bool up);

class GuardRunner {
public:
    GuardRunner(int socket, GuardInterfaces interfaces, GuardOptions options, std::unique_ptr<link::LinkAdmin> admin);
    // Until ecpaird is gone or asked for the shutdown. The exit code of the program.
    int run();

private:
    void report(const GuardMessage& message);

    int socket_;
    GuardInterfaces interfaces_;
    std::unique_ptr<link::LinkAdmin> admin_;
    GuardLogic logic_;
};

}  // namespace ecpair::linkguard
