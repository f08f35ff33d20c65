#pragma once
// A link sends and receives whole Ethernet frames on one network interface
// (or on an in-memory wire in tests). Frames are exactly what travels on the
// wire without the FCS. Links are not thread-safe for concurrent receives;
// send() may be called from another thread than receive().
//
// Implementations: PcapLink (a real interface, pcap_link.hpp) and MemoryLink
// (an in-memory wire, memory_link.hpp). Link state changes are observed
// through a LinkStateSource (link_state_source.hpp).

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <string>

#include "ecpair/common/bytes.hpp"
#include "ecpair/common/expected.hpp"
#include "ecpair/wire/mac_address.hpp"

namespace ecpair::link {

enum class LinkErrc : std::uint8_t {
    InterfaceNotFound,
    PermissionDenied,
    Closed,
    FrameTooLarge,
    SendFailed,
    ReceiveFailed,
    SystemError,
    InterfaceDown,  // administratively down when opened: worth retrying once it is set up
};

struct LinkError {
    LinkErrc code;
    std::string message;  // names the interface and the system's reason
};

using Clock = std::chrono::steady_clock;

// Names the error code ("InterfaceNotFound", ...) for logs and test output.
const char* to_string(LinkErrc code);

struct ReceivedFrame {
    std::size_t size = 0;         // bytes written into the caller's buffer
    std::size_t wire_size = 0;    // bytes on the wire (> size when truncated)
    Clock::time_point timestamp;  // steady clock, read when the link handed the frame over
    // Wall-clock time as a capture file records it: the kernel's receive
    // timestamp for pcap links, the send time for in-memory links.
    std::chrono::system_clock::time_point capture_time;
};

// What send_batch did: frames [0, sent) were taken by the adapter. When sent
// is less than the batch, `error` says why frame `sent` was not, and the
// frames after it were not tried.
struct BatchSendResult {
    std::size_t sent = 0;
    std::optional<LinkError> error;
};

class Link {
public:
    virtual ~Link() = default;
    Link() = default;
    Link(const Link&) = delete;
    Link& operator=(const Link&) = delete;

    virtual const std::string& name() const = 0;
    virtual wire::MacAddress mac() const = 0;

    // Sends one frame as is (no padding is added: the caller pads).
    virtual Expected<void, LinkError> send(ConstBytes frame) = 0;

    // Sends the frames in order, in as few system calls as the link can
    // (PcapLink: one sendmmsg per up to 64 frames). This default sends them
    // one by one with send().
    virtual BatchSendResult send_batch(std::span<const ConstBytes> frames);

    // Non-blocking: a frame if one is waiting, nullopt if none.
    virtual Expected<std::optional<ReceivedFrame>, LinkError> try_receive(Bytes buffer) = 0;

    // Blocks until a frame arrives or `timeout` passes (nullopt then).
    virtual Expected<std::optional<ReceivedFrame>, LinkError> receive(Bytes buffer,
                                                                      std::chrono::nanoseconds timeout) = 0;

    // A file descriptor that becomes readable when a frame may be waiting
    // (for poll/epoll or boost::asio::posix::stream_descriptor). Never -1.
    virtual int selectable_fd() const = 0;

    // Carrier / operational state as the kernel reports it now.
    virtual bool link_up() const = 0;
};

}  // namespace ecpair::link
