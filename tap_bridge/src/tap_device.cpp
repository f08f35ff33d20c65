#include "tap_device.hpp"

#include <arpa/inet.h>
#include <fcntl.h>
#include <linux/if_tun.h>
#include <linux/ipv6.h>
#include <net/if.h>  // struct ifreq as the other ioctl users have it (not linux/if.h's: one type per program)
#include <net/if_arp.h>
#include <netinet/in.h>
#include <sys/ioctl.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <fstream>

#include <fmt/format.h>

namespace ecpair::tap_bridge {
namespace {

// An ioctl socket of one family, closed on scope exit.
class IoctlSocket {
public:
    explicit IoctlSocket(int family) : fd_(::socket(family, SOCK_DGRAM | SOCK_CLOEXEC, 0)) {}
    ~IoctlSocket() {
        if (fd_ >= 0) ::close(fd_);
    }
    IoctlSocket(const IoctlSocket&) = delete;
    IoctlSocket& operator=(const IoctlSocket&) = delete;
    int fd() const { return fd_; }

private:
    int fd_;
};

ifreq request_for(const std::string& name) {
    ifreq r{};
    std::strncpy(r.ifr_name, name.c_str(), IFNAMSIZ - 1);
    return r;
}

std::string failure(const std::string& name, const char* step) {
    return fmt::format("TAP {}: {}: {}", name, step, std::strerror(errno));
}

Expected<void, std::string> set_ipv4(int fd, const std::string& name, const InterfaceAddress& a) {
    ifreq r = request_for(name);
    sockaddr_in address{};
    address.sin_family = AF_INET;
    std::memcpy(&address.sin_addr, a.bytes.data(), 4);
    std::memcpy(&r.ifr_addr, &address, sizeof address);
    if (::ioctl(fd, SIOCSIFADDR, &r) != 0) return unexpected(failure(name, "setting the IPv4 address"));
    sockaddr_in mask{};
    mask.sin_family = AF_INET;
    mask.sin_addr.s_addr = a.prefix_length == 0 ? 0 : htonl(~std::uint32_t{0} << (32 - a.prefix_length));
    std::memcpy(&r.ifr_netmask, &mask, sizeof mask);
    if (::ioctl(fd, SIOCSIFNETMASK, &r) != 0) return unexpected(failure(name, "setting the IPv4 netmask"));
    return {};
}

Expected<void, std::string> set_ipv6(const std::string& name, int ifindex, const InterfaceAddress& a) {
    // A namespace or host may have IPv6 off by default: an IPv6 address
    // configured on the bridge turns it on for this device.
    std::ofstream(fmt::format("/proc/sys/net/ipv6/conf/{}/disable_ipv6", name)) << "0\n";
    IoctlSocket socket6(AF_INET6);
    if (socket6.fd() < 0) return unexpected(failure(name, "opening an IPv6 socket (is IPv6 available?)"));
    in6_ifreq r{};
    std::memcpy(&r.ifr6_addr, a.bytes.data(), 16);
    r.ifr6_prefixlen = a.prefix_length;
    r.ifr6_ifindex = ifindex;
    if (::ioctl(socket6.fd(), SIOCSIFADDR, &r) != 0 && errno != EEXIST) {
        return unexpected(failure(name, "adding the IPv6 address"));
    }
    return {};
}

}  // namespace

Expected<std::unique_ptr<TapDevice>, std::string> TapDevice::open(const TapDeviceOptions& options) {
    if (options.name.empty() || options.name.size() >= IFNAMSIZ) {
        return unexpected(fmt::format("TAP name '{}': must be 1..{} characters", options.name, IFNAMSIZ - 1));
    }
    const int fd = ::open("/dev/net/tun", O_RDWR | O_NONBLOCK | O_CLOEXEC);
    if (fd < 0) return unexpected(failure(options.name, "opening /dev/net/tun"));
    ifreq r = request_for(options.name);
    r.ifr_flags = IFF_TAP | IFF_NO_PI;
    if (::ioctl(fd, TUNSETIFF, &r) != 0) {
        auto message = failure(options.name, "creating or attaching (TUNSETIFF; needs CAP_NET_ADMIN)");
        ::close(fd);
        return unexpected(std::move(message));
    }
    std::unique_ptr<TapDevice> device(new TapDevice(fd, r.ifr_name));
    const std::string& name = device->name_;

    IoctlSocket control(AF_INET);
    if (control.fd() < 0) return unexpected(failure(name, "opening a control socket"));
    if (options.mac) {
        ifreq m = request_for(name);
        m.ifr_hwaddr.sa_family = ARPHRD_ETHER;
        std::memcpy(m.ifr_hwaddr.sa_data, options.mac->bytes.data(), 6);
        if (::ioctl(control.fd(), SIOCSIFHWADDR, &m) != 0) return unexpected(failure(name, "setting the MAC address"));
    }
    ifreq m = request_for(name);
    if (::ioctl(control.fd(), SIOCGIFHWADDR, &m) != 0) return unexpected(failure(name, "reading the MAC address"));
    std::memcpy(device->mac_.bytes.data(), m.ifr_hwaddr.sa_data, 6);

    ifreq mtu = request_for(name);
    mtu.ifr_mtu = static_cast<int>(options.mtu);
    if (::ioctl(control.fd(), SIOCSIFMTU, &mtu) != 0) return unexpected(failure(name, "setting the MTU"));

    ifreq index = request_for(name);
    if (::ioctl(control.fd(), SIOCGIFINDEX, &index) != 0) return unexpected(failure(name, "reading the index"));
    ifreq flags = request_for(name);
    if (::ioctl(control.fd(), SIOCGIFFLAGS, &flags) != 0) return unexpected(failure(name, "reading the flags"));
    flags.ifr_flags = static_cast<short>(flags.ifr_flags | IFF_UP);
    if (::ioctl(control.fd(), SIOCSIFFLAGS, &flags) != 0) return unexpected(failure(name, "setting it up"));

    for (const auto& a : options.addresses) {
        auto set = a.family == InterfaceAddress::Family::Ipv4 ? set_ipv4(control.fd(), name, a)
                                                              : set_ipv6(name, index.ifr_ifindex, a);
        if (!set) return unexpected(set.error());
    }
    return device;
}

TapDevice::~TapDevice() {
    if (fd_ >= 0) ::close(fd_);
}

long TapDevice::read(Bytes buffer) const {
    const auto n = ::read(fd_, buffer.data(), buffer.size());
    if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK)) return 0;
    return n;
}

bool TapDevice::write(ConstBytes frame) const {
    return ::write(fd_, frame.data(), frame.size()) == static_cast<ssize_t>(frame.size());
}

}  // namespace ecpair::tap_bridge
