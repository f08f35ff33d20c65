// SIOCGIFHWADDR and SIOCGIFFLAGS on an AF_INET datagram socket: both are
// answered by the generic device layer for any socket family, and an AF_INET
// datagram socket needs no privilege.

#include "interface_query.hpp"

#include <linux/ethtool.h>
#include <linux/sockios.h>

#include <net/if.h>
#include <net/if_arp.h>
#include <sys/ioctl.h>
#include <sys/socket.h>

#include <algorithm>
#include <cerrno>
#include <cstring>

namespace ecpair::link::detail {
namespace {

ifreq request_for(const std::string& ifname) {
    ifreq request{};
    std::memcpy(request.ifr_name, ifname.data(), std::min(ifname.size(), sizeof(request.ifr_name) - 1));
    return request;
}

}  // namespace

Expected<InterfaceQuery, int> InterfaceQuery::open(std::string ifname) {
    if (ifname.empty() || ifname.size() >= IFNAMSIZ) return unexpected(ENODEV);
    UniqueFd socket(::socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0));
    if (!socket.valid()) return unexpected(errno);
    ifreq request = request_for(ifname);
    if (::ioctl(socket.get(), SIOCGIFFLAGS, &request) != 0) return unexpected(errno);
    return InterfaceQuery(std::move(ifname), std::move(socket));
}

Expected<wire::MacAddress, int> InterfaceQuery::mac() const {
    ifreq request = request_for(ifname_);
    if (::ioctl(socket_.get(), SIOCGIFHWADDR, &request) != 0) return unexpected(errno);
    if (request.ifr_hwaddr.sa_family != ARPHRD_ETHER) return unexpected(EINVAL);
    wire::MacAddress mac;
    std::memcpy(mac.bytes.data(), request.ifr_hwaddr.sa_data, mac.bytes.size());
    return mac;
}

bool InterfaceQuery::running() const {
    ifreq request = request_for(ifname_);
    if (::ioctl(socket_.get(), SIOCGIFFLAGS, &request) != 0) return false;
    const auto flags = static_cast<unsigned>(request.ifr_flags);
    if ((flags & IFF_UP) == 0) return false;
    // IFF_RUNNING follows the operational state, which the kernel updates up
    // to a second after the carrier changes (linkwatch). The driver's link
    // status (ethtool GLINK) is the carrier itself, at once.
    ethtool_value link{};
    link.cmd = ETHTOOL_GLINK;
    ifreq glink = request_for(ifname_);
    glink.ifr_data = reinterpret_cast<char*>(&link);
    if (::ioctl(socket_.get(), SIOCETHTOOL, &glink) == 0) return link.data != 0;
    return (flags & IFF_RUNNING) != 0;
}

}  // namespace ecpair::link::detail
