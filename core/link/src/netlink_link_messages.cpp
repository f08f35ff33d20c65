// A datagram is a sequence of messages, each an nlmsghdr (length includes
// the header) padded to 4 bytes. A link message's payload is an ifinfomsg
// followed by attributes, each an rtattr (length includes the header) padded
// to 4 bytes. Kernel structures are copied out with memcpy (the buffer has no
// alignment guarantee) after the bytes they occupy have been checked.

#include "netlink_link_messages.hpp"

// glibc's <net/if.h> first: <linux/if.h> then leaves out what glibc defines,
// so both may meet in one translation unit (a unity build).
#include <net/if.h>
#include <linux/if.h>
#include <linux/netlink.h>
#include <linux/rtnetlink.h>
#include <sys/socket.h>

#include <algorithm>
#include <cstring>

#include <fmt/format.h>

namespace ecpair::link::detail {
namespace {

template <class T>
T copy_out(ConstBytes bytes, std::size_t offset) {
    T value{};
    std::memcpy(&value, bytes.data() + offset, sizeof(T));
    return value;
}

constexpr std::size_t align4(std::size_t length) { return (length + 3) & ~std::size_t{3}; }

Unexpected<NetlinkDecodeError> problem_at(std::size_t offset, std::string problem) {
    return unexpected(NetlinkDecodeError{offset, std::move(problem)});
}

// `attributes` spans from the first rtattr to the end of the message;
// `base` is its offset in the datagram, for error reports.
Expected<void, NetlinkDecodeError> decode_link_attributes(ConstBytes attributes, std::size_t base,
                                                          LinkMessage& link) {
    std::size_t offset = 0;
    while (attributes.size() - offset >= sizeof(rtattr)) {
        const auto header = copy_out<rtattr>(attributes, offset);
        if (header.rta_len < sizeof(rtattr) || header.rta_len > attributes.size() - offset) {
            return problem_at(base + offset, fmt::format("attribute length {} does not fit the {} bytes left",
                                                         header.rta_len, attributes.size() - offset));
        }
        const ConstBytes payload = attributes.subspan(offset + sizeof(rtattr), header.rta_len - sizeof(rtattr));
        const auto type = static_cast<unsigned>(header.rta_type & NLA_TYPE_MASK);
        if (type == IFLA_IFNAME) {
            const auto end = std::find(payload.begin(), payload.end(), std::uint8_t{0});
            link.name.assign(payload.begin(), end);
            if (link.name.size() >= IFNAMSIZ) {
                return problem_at(base + offset, fmt::format("interface name of {} bytes is too long", link.name.size()));
            }
        } else if (type == IFLA_OPERSTATE || type == IFLA_CARRIER) {
            if (payload.empty()) return problem_at(base + offset, fmt::format("empty attribute of type {}", type));
            if (type == IFLA_OPERSTATE) {
                link.operstate = payload[0];
            } else {
                link.carrier = payload[0] != 0;
            }
        }
        offset = std::min(attributes.size(), offset + align4(header.rta_len));
    }
    return {};
}

Expected<LinkMessage, NetlinkDecodeError> decode_link_message(ConstBytes payload, std::size_t base,
                                                              std::uint16_t type) {
    if (payload.size() < sizeof(ifinfomsg)) {
        return problem_at(base, fmt::format("link message payload of {} bytes is shorter than ifinfomsg ({})",
                                            payload.size(), sizeof(ifinfomsg)));
    }
    const auto info = copy_out<ifinfomsg>(payload, 0);
    LinkMessage link;
    link.kind = type == RTM_DELLINK ? LinkMessage::Kind::Deleted : LinkMessage::Kind::New;
    link.index = info.ifi_index;
    link.flags = info.ifi_flags;
    const std::size_t attributes_at = std::min(payload.size(), align4(sizeof(ifinfomsg)));
    if (auto decoded = decode_link_attributes(payload.subspan(attributes_at), base + attributes_at, link); !decoded) {
        return unexpected(decoded.error());
    }
    return link;
}

}  // namespace

bool LinkMessage::is_up() const {
    if (kind == Kind::Deleted) return false;
    if ((flags & IFF_UP) == 0 || (flags & IFF_RUNNING) == 0) return false;
    if (carrier && !*carrier) return false;
    return !operstate || *operstate == IF_OPER_UP || *operstate == IF_OPER_UNKNOWN;
}

Expected<NetlinkBatch, NetlinkDecodeError> decode_netlink_link_messages(ConstBytes datagram) {
    NetlinkBatch batch;
    std::size_t offset = 0;
    while (offset < datagram.size()) {
        const std::size_t left = datagram.size() - offset;
        if (left < sizeof(nlmsghdr)) {
            return problem_at(offset, fmt::format("{} trailing bytes are too few for a message header", left));
        }
        const auto header = copy_out<nlmsghdr>(datagram, offset);
        if (header.nlmsg_len < sizeof(nlmsghdr) || header.nlmsg_len > left) {
            return problem_at(offset,
                              fmt::format("message length {} does not fit the {} bytes left", header.nlmsg_len, left));
        }
        if (offset == 0) batch.sequence = header.nlmsg_seq;
        const std::size_t payload_at = offset + sizeof(nlmsghdr);
        const ConstBytes payload = datagram.subspan(payload_at, header.nlmsg_len - sizeof(nlmsghdr));
        switch (header.nlmsg_type) {
            case NLMSG_DONE:
                batch.dump_done = true;
                break;
            case NLMSG_ERROR:
                if (payload.size() < sizeof(int)) {
                    return problem_at(payload_at, "error message without an error code");
                }
                batch.error = copy_out<int>(payload, 0);
                batch.acknowledged = true;
                break;
            case RTM_NEWLINK:
            case RTM_DELLINK: {
                auto link = decode_link_message(payload, payload_at, header.nlmsg_type);
                if (!link) return unexpected(link.error());
                batch.links.push_back(std::move(link).value());
                break;
            }
            default:
                break;
        }
        offset = std::min(datagram.size(), offset + align4(header.nlmsg_len));
    }
    return batch;
}

std::array<std::uint8_t, kLinkDumpRequestSize> encode_link_dump_request(std::uint32_t sequence) {
    static_assert(sizeof(nlmsghdr) + sizeof(ifinfomsg) == kLinkDumpRequestSize);
    nlmsghdr header{};
    header.nlmsg_len = kLinkDumpRequestSize;
    header.nlmsg_type = RTM_GETLINK;
    header.nlmsg_flags = NLM_F_REQUEST | NLM_F_DUMP;
    header.nlmsg_seq = sequence;
    ifinfomsg request{};
    request.ifi_family = AF_UNSPEC;

    std::array<std::uint8_t, kLinkDumpRequestSize> out{};
    std::memcpy(out.data(), &header, sizeof(header));
    std::memcpy(out.data() + sizeof(header), &request, sizeof(request));
    return out;
}

namespace {

// nlmsghdr + ifinfomsg + an IFLA_IFNAME attribute.
std::vector<std::uint8_t> encode_named_link_request(std::uint16_t type, std::uint32_t sequence,
                                                    const std::string& ifname, unsigned change, unsigned flags) {
    const std::size_t name_size = ifname.size() + 1;  // with the terminating NUL
    const std::size_t attribute_size = sizeof(rtattr) + name_size;
    const std::size_t total = sizeof(nlmsghdr) + align4(sizeof(ifinfomsg)) + align4(attribute_size);
    nlmsghdr header{};
    header.nlmsg_len = static_cast<std::uint32_t>(total);
    header.nlmsg_type = type;
    header.nlmsg_flags = NLM_F_REQUEST | NLM_F_ACK;
    header.nlmsg_seq = sequence;
    ifinfomsg info{};
    info.ifi_family = AF_UNSPEC;
    info.ifi_index = 0;  // addressed by IFLA_IFNAME
    info.ifi_change = change;
    info.ifi_flags = flags;
    rtattr attribute{};
    attribute.rta_len = static_cast<unsigned short>(attribute_size);
    attribute.rta_type = IFLA_IFNAME;

    std::vector<std::uint8_t> out(total, 0);
    std::size_t at = 0;
    std::memcpy(out.data() + at, &header, sizeof(header));
    at += sizeof(header);
    std::memcpy(out.data() + at, &info, sizeof(info));
    at += align4(sizeof(info));
    std::memcpy(out.data() + at, &attribute, sizeof(attribute));
    at += sizeof(attribute);
    std::memcpy(out.data() + at, ifname.c_str(), name_size);
    return out;
}

}  // namespace

std::vector<std::uint8_t> encode_link_admin_request(std::uint32_t sequence, const std::string& ifname, bool up) {
    return encode_named_link_request(RTM_NEWLINK, sequence, ifname, IFF_UP, up ? static_cast<unsigned>(IFF_UP) : 0u);
}

std::vector<std::uint8_t> encode_link_get_request(std::uint32_t sequence, const std::string& ifname) {
    return encode_named_link_request(RTM_GETLINK, sequence, ifname, 0, 0);
}

}  // namespace ecpair::link::detail
