#pragma once
// The kernel TAP device (Documentation/networking/tuntap.rst): /dev/net/tun
// with IFF_TAP | IFF_NO_PI gives one Ethernet frame per read() and write().
// TUNSETIFF creates the device, or attaches to an existing persistent one of
// that name. Then MAC, MTU, addresses and IFF_UP are set with the classic
// interface ioctls (IPv6 addresses through an AF_INET6 socket). The fd is
// non-blocking; the TAP I/O thread waits on it with poll().

#include <cstddef>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "ecpair/common/bytes.hpp"
#include "ecpair/common/expected.hpp"
#include "ecpair/tap_bridge/interface_address.hpp"
#include "ecpair/wire/mac_address.hpp"

namespace ecpair::tap_bridge {

struct TapDeviceOptions {
    std::string name;
    std::optional<wire::MacAddress> mac;
    std::size_t mtu = 0;
    std::vector<InterfaceAddress> addresses;
};

class TapDevice {
public:
    // Errors name the device and the step that failed.
    static Expected<std::unique_ptr<TapDevice>, std::string> open(const TapDeviceOptions& options);
    ~TapDevice();
    TapDevice(const TapDevice&) = delete;
    TapDevice& operator=(const TapDevice&) = delete;

    int fd() const { return fd_; }
    const std::string& name() const { return name_; }
    wire::MacAddress mac() const { return mac_; }

    // One frame; 0 when none is waiting, -1 on an error (errno set).
    long read(Bytes buffer) const;
    bool write(ConstBytes frame) const;

private:
    TapDevice(int fd, std::string name) : fd_(fd), name_(std::move(name)) {}

    int fd_ = -1;
    std::string name_;
    wire::MacAddress mac_;
};

}  // namespace ecpair::tap_bridge
