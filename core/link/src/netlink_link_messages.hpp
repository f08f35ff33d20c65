#pragma once
// The rtnetlink messages a LinkStateMonitor and a LinkAdmin exchange with the
// kernel: the requests they send (an RTM_GETLINK dump; RTM_NEWLINK setting
// IFF_UP and RTM_GETLINK of one interface by name), and the datagrams they
// receive (RTM_NEWLINK / RTM_DELLINK, NLMSG_DONE, NLMSG_ERROR). Received bytes are
// treated as untrusted: every length is checked before it is used, and a
// malformed datagram gives an error naming the byte offset and the problem.

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "ecpair/common/bytes.hpp"
#include "ecpair/common/expected.hpp"

namespace ecpair::link::detail {

// What one RTM_NEWLINK / RTM_DELLINK message says about an interface.
struct LinkMessage {
    enum class Kind : std::uint8_t { New, Deleted };

    Kind kind = Kind::New;
    int index = 0;                          // ifi_index
    std::string name;                       // IFLA_IFNAME; empty when absent
    unsigned flags = 0;                     // ifi_flags: IFF_UP, IFF_RUNNING, ...
    std::optional<std::uint8_t> operstate;  // IFLA_OPERSTATE (RFC 2863 IF_OPER_*)
    std::optional<bool> carrier;            // IFLA_CARRIER

    // Frames can flow: the interface exists, is up and running (IFF_RUNNING
    // is the kernel's digest of carrier and operational state), and, when
    // reported, the carrier is on and the operational state is "up" or
    // "unknown" (the latter for drivers without carrier reporting).
    bool is_up() const;
};

// Everything one datagram carried that a link monitor cares about.
struct NetlinkBatch {
    std::vector<LinkMessage> links;
    bool dump_done = false;  // NLMSG_DONE: the end of a dump
    int error = 0;           // of an NLMSG_ERROR: a negative errno (0: none, or an ack)
    bool acknowledged = false;  // an NLMSG_ERROR came (error or ack): the request is answered
    std::uint32_t sequence = 0;  // nlmsg_seq of the datagram's first message
};

struct NetlinkDecodeError {
    std::size_t offset = 0;  // byte offset in the datagram
    std::string problem;
};

// Decodes one datagram read from a NETLINK_ROUTE socket. Message types other
// than the above are skipped.
Expected<NetlinkBatch, NetlinkDecodeError> decode_netlink_link_messages(ConstBytes datagram);

// Size of the RTM_GETLINK dump request.
inline constexpr std::size_t kLinkDumpRequestSize = 32;

// An RTM_GETLINK request for all interfaces (NLM_F_DUMP).
std::array<std::uint8_t, kLinkDumpRequestSize> encode_link_dump_request(std::uint32_t sequence);

// An RTM_NEWLINK request that sets (`up`) or clears IFF_UP of the interface
// named `ifname` (shorter than IFNAMSIZ), asking for an acknowledgement.
std::vector<std::uint8_t> encode_link_admin_request(std::uint32_t sequence, const std::string& ifname, bool up);
// An RTM_GETLINK request for the one interface named `ifname`, with an acknowledgement.
std::vector<std::uint8_t> encode_link_get_request(std::uint32_t sequence, const std::string& ifname);

}  // namespace ecpair::link::detail
