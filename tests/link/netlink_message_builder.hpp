#pragma once
// Builds rtnetlink datagrams the way the kernel lays them out, for the
// decoder tests and the fuzz corpus generator.

#include <linux/if.h>
#include <linux/netlink.h>
#include <linux/rtnetlink.h>

#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

namespace ecpair::link::test {

class NetlinkDatagram {
public:
    // An RTM_NEWLINK / RTM_DELLINK message; attributes follow via the add_* calls.
    NetlinkDatagram& link(std::uint16_t type, int index, unsigned flags) {
        begin_message(type);
        ifinfomsg info{};
        info.ifi_index = index;
        info.ifi_flags = flags;
        append(&info, sizeof(info));
        return *this;
    }
    NetlinkDatagram& name(const std::string& ifname) {
        return attribute(IFLA_IFNAME, ifname.c_str(), ifname.size() + 1);
    }
    NetlinkDatagram& operstate(std::uint8_t state) { return attribute(IFLA_OPERSTATE, &state, 1); }
    NetlinkDatagram& carrier(bool on) {
        const std::uint8_t value = on ? 1 : 0;
        return attribute(IFLA_CARRIER, &value, 1);
    }
    NetlinkDatagram& attribute(std::uint16_t type, const void* data, std::size_t size) {
        rtattr header{};
        header.rta_len = static_cast<std::uint16_t>(sizeof(rtattr) + size);
        header.rta_type = type;
        append(&header, sizeof(header));
        append(data, size);
        pad();
        return *this;
    }
    NetlinkDatagram& done() {
        begin_message(NLMSG_DONE);
        const int zero = 0;
        append(&zero, sizeof(zero));
        return *this;
    }
    NetlinkDatagram& error(int code) {
        begin_message(NLMSG_ERROR);
        nlmsgerr body{};
        body.error = code;
        append(&body, sizeof(body));
        return *this;
    }
    NetlinkDatagram& other(std::uint16_t type, std::size_t payload_size) {
        begin_message(type);
        bytes_.resize(bytes_.size() + payload_size);
        return *this;
    }

    // The finished datagram (message lengths filled in).
    std::vector<std::uint8_t> bytes() {
        finish_message();
        return bytes_;
    }

private:
    void begin_message(std::uint16_t type) {
        finish_message();
        pad();
        message_start_ = bytes_.size();
        nlmsghdr header{};
        header.nlmsg_type = type;
        append(&header, sizeof(header));
        open_ = true;
    }
    void finish_message() {
        if (!open_) return;
        const auto length = static_cast<std::uint32_t>(bytes_.size() - message_start_);
        std::memcpy(bytes_.data() + message_start_, &length, sizeof(length));
        open_ = false;
    }
    void append(const void* data, std::size_t size) {
        const auto* begin = static_cast<const std::uint8_t*>(data);
        bytes_.insert(bytes_.end(), begin, begin + size);
    }
    void pad() { bytes_.resize((bytes_.size() + 3) & ~std::size_t{3}); }

    std::vector<std::uint8_t> bytes_;
    std::size_t message_start_ = 0;
    bool open_ = false;
};

}  // namespace ecpair::link::test
