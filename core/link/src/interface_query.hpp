#pragma once
// Asks the kernel about one network interface by name (hardware address,
// up/running flags) through ioctls on a datagram socket. The socket is made
// in the network namespace of the thread that opens the query and stays bound
// to it, so the answers stay right when later calls come from a thread in
// another namespace. (/sys/class/net would not: it shows the namespace of
// whoever mounted sysfs.)

#include <string>

#include "ecpair/common/expected.hpp"
#include "ecpair/wire/mac_address.hpp"
#include "unique_fd.hpp"

namespace ecpair::link::detail {

class InterfaceQuery {
public:
    // Errors are errno values (ENODEV: no such interface).
    static Expected<InterfaceQuery, int> open(std::string ifname);

    // The Ethernet address; EINVAL when the interface is not Ethernet.
    Expected<wire::MacAddress, int> mac() const;

    // Administratively up and operationally up (carrier): IFF_UP and
    // IFF_RUNNING. False when the interface is gone.
    bool running() const;

private:
    InterfaceQuery(std::string ifname, UniqueFd socket) : ifname_(std::move(ifname)), socket_(std::move(socket)) {}

    std::string ifname_;
    UniqueFd socket_;
};

}  // namespace ecpair::link::detail
