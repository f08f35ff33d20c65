#pragma once
// Sets kernel network interfaces administratively up or down (IFF_UP) and
// reads that flag back, over rtnetlink (RTM_NEWLINK / RTM_GETLINK addressed
// by interface name, each acknowledged by the kernel). Setting a veth end
// down takes the carrier from both ends, as pulling the cable would; this is
// how the link guard takes a failed master's links down (acontis REQ012).
//
// The socket belongs to the network namespace of the thread that opens the
// LinkAdmin and keeps acting there. Needs CAP_NET_ADMIN to change a link.

#include <chrono>
#include <memory>
#include <string>

#include "ecpair/common/expected.hpp"
#include "ecpair/link/link.hpp"

namespace ecpair::link {

class LinkAdmin {
public:
    static Expected<std::unique_ptr<LinkAdmin>, LinkError> open();
    ~LinkAdmin();
    LinkAdmin(const LinkAdmin&) = delete;
    LinkAdmin& operator=(const LinkAdmin&) = delete;

    // Sets IFF_UP (up) or clears it (down); waits for the kernel's answer.
    // Errors name the interface: InterfaceNotFound, PermissionDenied, SystemError.
    Expected<void, LinkError> set_up(const std::string& ifname, bool up);
    // Whether IFF_UP is set (the administrative state, not the carrier).
    Expected<bool, LinkError> is_up(const std::string& ifname);

private:
    explicit LinkAdmin(int socket) : socket_(socket) {}
    // Sends a request and reads datagrams until the kernel's answer to it.
    Expected<std::optional<unsigned>, LinkError> exchange(const std::string& ifname, bool get, bool up);

    int socket_;
    std::uint32_t sequence_ = 0;
    static constexpr std::chrono::seconds kAnswerTimeout{2};
};

}  // namespace ecpair::link
