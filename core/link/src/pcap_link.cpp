// PcapLink: opening a capture the way an EtherCAT master needs it, and the
// three operations on it.
//
// open():   pcap_create -> snaplen/promiscuous/immediate/timeout ->
//           pcap_activate -> Ethernet check -> non-blocking -> inbound only
//           -> optional BPF filter -> selectable fd -> the interface's MAC.
//           Each failure becomes a LinkError naming the interface.
// send():   pcap_inject of the frame as given (the caller pads).
// send_batch(): sendmmsg on the link's own AF_PACKET socket (see the header),
//           in chunks of kBatchChunk frames, from preallocated headers.
// receive:  pcap_next_ex in non-blocking mode; the blocking variant tries,
//           then sleeps in poll() on the selectable fd until the deadline.
//
// libpcap's handle, including its error buffer, is not safe for concurrent
// use, and send() may run on another thread than the receives: a mutex
// serialises the (non-blocking, short) pcap calls. poll() runs unlocked.
//
// When the interface goes down or disappears, libpcap may answer a read with
// an error ("The interface went down", "The interface disappeared"), and
// capture resumes when the interface comes back. try_receive turns such an
// error into "no frame" when the interface is indeed not running, so a pulled
// cable never surfaces as a receive failure (the fd does not stay readable,
// so a blocking receive still sleeps).

#include "ecpair/link/pcap_link.hpp"

#include <linux/if_packet.h>
#include <net/if.h>
#include <pcap/pcap.h>
#include <sys/socket.h>
#include <sys/uio.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cstring>
#include <mutex>
#include <system_error>

#include <fmt/format.h>

#include "ecpair/common/log.hpp"
#include "ecpair/wire/constants.hpp"
#include "interface_query.hpp"
#include "unique_fd.hpp"
#include "wait_readable.hpp"

namespace ecpair::link {
namespace {

// Frames are at most 1518 bytes; 2048 leaves room and keeps ring slots small.
constexpr int kSnapLength = 2048;
// Frames per sendmmsg call (a cycle of 512 slaves sends about 60 per link).
constexpr std::size_t kBatchChunk = 64;

struct PcapCloser {
    void operator()(pcap_t* handle) const { pcap_close(handle); }
};
using PcapHandle = std::unique_ptr<pcap_t, PcapCloser>;

Unexpected<LinkError> fail(LinkErrc code, const std::string& ifname, const std::string& reason) {
    return unexpected(LinkError{code, fmt::format("interface '{}': {}", ifname, reason)});
}

std::string with_pcap_detail(const std::string& reason, const char* pcap_message) {
    if (pcap_message == nullptr || *pcap_message == '\0') return reason;
    return fmt::format("{} (pcap: {})", reason, pcap_message);
}

Unexpected<LinkError> activation_error(const std::string& ifname, int status, pcap_t* handle) {
    const char* detail = pcap_geterr(handle);
    switch (status) {
        case PCAP_ERROR_NO_SUCH_DEVICE:
            return fail(LinkErrc::InterfaceNotFound, ifname, with_pcap_detail("no such device", detail));
        case PCAP_ERROR_PERM_DENIED:
        case PCAP_ERROR_PROMISC_PERM_DENIED:
            return fail(LinkErrc::PermissionDenied, ifname,
                        with_pcap_detail("permission denied (capturing needs CAP_NET_RAW)", detail));
        case PCAP_ERROR_IFACE_NOT_UP:
            return fail(LinkErrc::InterfaceDown, ifname, with_pcap_detail("interface is administratively down", detail));
        default:
            return fail(LinkErrc::SystemError, ifname,
                        with_pcap_detail(fmt::format("cannot activate capture: {}", pcap_statustostr(status)), detail));
    }
}

Expected<void, LinkError> install_filter(pcap_t* handle, const std::string& ifname, const std::string& expression) {
    bpf_program program{};
    if (pcap_compile(handle, &program, expression.c_str(), 1, PCAP_NETMASK_UNKNOWN) != 0) {
        return fail(LinkErrc::SystemError, ifname,
                    fmt::format("invalid BPF filter \"{}\": {}", expression, pcap_geterr(handle)));
    }
    const int installed = pcap_setfilter(handle, &program);
    pcap_freecode(&program);
    if (installed != 0) {
        return fail(LinkErrc::SystemError, ifname,
                    fmt::format("cannot install BPF filter \"{}\": {}", expression, pcap_geterr(handle)));
    }
    return {};
}

std::chrono::system_clock::time_point to_system_time(const timeval& time) {
    const auto since_epoch = std::chrono::seconds(time.tv_sec) + std::chrono::microseconds(time.tv_usec);
    return std::chrono::system_clock::time_point(
        std::chrono::duration_cast<std::chrono::system_clock::duration>(since_epoch));
}

// A packet socket that only sends, bound to the interface (errno on failure).
Expected<detail::UniqueFd, int> open_send_socket(const std::string& ifname) {
    const unsigned index = if_nametoindex(ifname.c_str());
    if (index == 0) return unexpected(errno);
    detail::UniqueFd fd(::socket(AF_PACKET, SOCK_RAW | SOCK_CLOEXEC, 0));
    if (!fd.valid()) return unexpected(errno);
    sockaddr_ll address{};
    address.sll_family = AF_PACKET;
    address.sll_protocol = 0;  // receive nothing
    address.sll_ifindex = static_cast<int>(index);
    if (::bind(fd.get(), reinterpret_cast<const sockaddr*>(&address), sizeof address) != 0) return unexpected(errno);
    return fd;
}

}  // namespace

struct PcapLink::Impl {
    Impl(PcapHandle handle, detail::InterfaceQuery query, detail::UniqueFd send_socket)
        : pcap(std::move(handle)), interface(std::move(query)), batch_socket(std::move(send_socket)) {}

    PcapHandle pcap;
    detail::InterfaceQuery interface;
    std::mutex pcap_mutex;

    detail::UniqueFd batch_socket;
    std::mutex batch_mutex;  // guards the headers below
    std::array<mmsghdr, kBatchChunk> headers{};
    std::array<iovec, kBatchChunk> vectors{};
};

Expected<std::unique_ptr<PcapLink>, LinkError> PcapLink::open(const std::string& ifname,
                                                              const PcapLinkOptions& options) {
    char errbuf[PCAP_ERRBUF_SIZE] = {};
    PcapHandle handle(pcap_create(ifname.c_str(), errbuf));
    if (!handle) return fail(LinkErrc::SystemError, ifname, fmt::format("pcap_create: {}", errbuf));

    pcap_t* const pcap = handle.get();
    pcap_set_snaplen(pcap, kSnapLength);
    pcap_set_promisc(pcap, 1);
    pcap_set_immediate_mode(pcap, 1);
    pcap_set_timeout(pcap, static_cast<int>(options.pcap_timeout.count()));

    const int activated = pcap_activate(pcap);
    if (activated < 0) return activation_error(ifname, activated, pcap);
    if (activated > 0) {
        logger("link")->warn("interface '{}': {}", ifname,
                             with_pcap_detail(pcap_statustostr(activated), pcap_geterr(pcap)));
    }

    if (const int link_type = pcap_datalink(pcap); link_type != DLT_EN10MB) {
        return fail(LinkErrc::SystemError, ifname,
                    fmt::format("not an Ethernet interface (pcap link type {})", link_type));
    }
    if (pcap_setnonblock(pcap, 1, errbuf) != 0) {
        return fail(LinkErrc::SystemError, ifname, fmt::format("cannot make capture non-blocking: {}", errbuf));
    }
    if (pcap_setdirection(pcap, PCAP_D_IN) != 0) {
        return fail(LinkErrc::SystemError, ifname,
                    fmt::format("cannot capture inbound frames only: {}", pcap_geterr(pcap)));
    }
    // libpcap drops outbound frames only after the kernel copied them into
    // the capture ring; asking the kernel to leave them out saves that copy
    // of every frame this host sends on the interface (Linux 4.20 and later).
    const int ignore_outgoing = 1;
    if (setsockopt(pcap_get_selectable_fd(pcap), SOL_PACKET, PACKET_IGNORE_OUTGOING, &ignore_outgoing,
                   sizeof ignore_outgoing) != 0) {
        logger("link")->debug("interface '{}': outbound frames are filtered by libpcap ({})", ifname,
                              std::system_category().message(errno));
    }
    if (options.bpf_filter) {
        if (auto installed = install_filter(pcap, ifname, *options.bpf_filter); !installed) {
            return unexpected(installed.error());
        }
    }
    const int selectable_fd = pcap_get_selectable_fd(pcap);
    if (selectable_fd < 0) return fail(LinkErrc::SystemError, ifname, "capture has no selectable file descriptor");

    auto interface = detail::InterfaceQuery::open(ifname);
    if (!interface) {
        const LinkErrc code = interface.error() == ENODEV ? LinkErrc::InterfaceNotFound : LinkErrc::SystemError;
        return fail(code, ifname, std::system_category().message(interface.error()));
    }
    auto mac = interface->mac();
    if (!mac) {
        return fail(LinkErrc::SystemError, ifname,
                    fmt::format("cannot read the hardware address: {}", std::system_category().message(mac.error())));
    }

    auto send_socket = open_send_socket(ifname);
    if (!send_socket) {
        return fail(send_socket.error() == EPERM ? LinkErrc::PermissionDenied : LinkErrc::SystemError, ifname,
                    fmt::format("cannot open the packet socket for batches: {}",
                                std::system_category().message(send_socket.error())));
    }

    auto impl = std::make_unique<Impl>(std::move(handle), std::move(interface).value(), std::move(send_socket).value());
    logger("link")->info("interface '{}' opened (mac {}, filter {})", ifname, mac->to_string(),
                         options.bpf_filter.value_or("none"));
    return std::unique_ptr<PcapLink>(new PcapLink(ifname, *mac, std::move(impl), selectable_fd));
}

PcapLink::PcapLink(std::string ifname, wire::MacAddress mac, std::unique_ptr<Impl> impl, int selectable_fd)
    : ifname_(std::move(ifname)), mac_(mac), impl_(std::move(impl)), selectable_fd_(selectable_fd) {}

PcapLink::~PcapLink() = default;

Expected<void, LinkError> PcapLink::send(ConstBytes frame) {
    if (frame.size() > wire::kMaxFrameSizeVlan) {
        return fail(LinkErrc::FrameTooLarge, ifname_,
                    fmt::format("frame of {} bytes is larger than {}", frame.size(), wire::kMaxFrameSizeVlan));
    }
    std::lock_guard lock(impl_->pcap_mutex);
    int sent = pcap_inject(impl_->pcap.get(), frame.data(), frame.size());
    if (sent < 0 && impl_->interface.running()) {
        // The socket keeps the error of an interface that went down until it
        // has been reported once; the link is up again, so that error is
        // stale: send again.
        sent = pcap_inject(impl_->pcap.get(), frame.data(), frame.size());
    }
    if (sent < 0) return fail(LinkErrc::SendFailed, ifname_, fmt::format("send failed: {}", pcap_geterr(impl_->pcap.get())));
    if (static_cast<std::size_t>(sent) != frame.size()) {
        return fail(LinkErrc::SendFailed, ifname_, fmt::format("sent {} of {} bytes", sent, frame.size()));
    }
    return {};
}

BatchSendResult PcapLink::send_batch(std::span<const ConstBytes> frames) {
    BatchSendResult result;
    std::lock_guard lock(impl_->batch_mutex);
    bool retried = false;
    while (result.sent < frames.size()) {
        // The next chunk: up to kBatchChunk frames, ending before one that is too large.
        const auto rest = frames.subspan(result.sent, std::min(kBatchChunk, frames.size() - result.sent));
        std::size_t count = 0;
        for (; count < rest.size() && rest[count].size() <= wire::kMaxFrameSizeVlan; ++count) {
            impl_->vectors[count] = iovec{const_cast<std::uint8_t*>(rest[count].data()), rest[count].size()};
            impl_->headers[count] = mmsghdr{};
            impl_->headers[count].msg_hdr.msg_iov = &impl_->vectors[count];
            impl_->headers[count].msg_hdr.msg_iovlen = 1;
        }
        if (count == 0) {
            result.error = LinkError{LinkErrc::FrameTooLarge,
                                     fmt::format("interface '{}': frame of {} bytes is larger than {}", ifname_,
                                                 rest[0].size(), wire::kMaxFrameSizeVlan)};
            return result;
        }
        const int sent = ::sendmmsg(impl_->batch_socket.get(), impl_->headers.data(), static_cast<unsigned>(count), 0);
        if (sent > 0) {
            result.sent += static_cast<std::size_t>(sent);
            continue;
        }
        const int error = errno;
        if (error == EINTR) continue;
        // As in send(): an error kept from when the interface went down is stale once it is back up.
        if (!retried && impl_->interface.running()) {
            retried = true;
            continue;
        }
        result.error = LinkError{LinkErrc::SendFailed, fmt::format("interface '{}': send failed: {}", ifname_,
                                                                   std::system_category().message(error))};
        return result;
    }
    return result;
}

Expected<std::optional<ReceivedFrame>, LinkError> PcapLink::try_receive(Bytes buffer) {
    std::lock_guard lock(impl_->pcap_mutex);
    pcap_pkthdr* header = nullptr;
    const u_char* data = nullptr;
    const int status = pcap_next_ex(impl_->pcap.get(), &header, &data);
    if (status == 1) {
        const std::size_t size = std::min<std::size_t>(header->caplen, buffer.size());
        std::copy_n(data, size, buffer.begin());
        return std::optional<ReceivedFrame>(ReceivedFrame{size, header->len, Clock::now(), to_system_time(header->ts)});
    }
    if (status == 0) return std::optional<ReceivedFrame>();
    if (!impl_->interface.running()) {
        logger("link")->debug("interface '{}' is down: {}", ifname_, pcap_geterr(impl_->pcap.get()));
        return std::optional<ReceivedFrame>();
    }
    return fail(LinkErrc::ReceiveFailed, ifname_, fmt::format("receive failed: {}", pcap_geterr(impl_->pcap.get())));
}

Expected<std::optional<ReceivedFrame>, LinkError> PcapLink::receive(Bytes buffer, std::chrono::nanoseconds timeout) {
    const auto deadline = Clock::now() + timeout;
    while (true) {
        auto received = try_receive(buffer);
        if (!received || received->has_value()) return received;
        const auto left = deadline - Clock::now();
        if (left <= Clock::duration::zero()) return received;
        if (auto ready = detail::wait_readable(selectable_fd_, left); !ready) {
            return fail(LinkErrc::ReceiveFailed, ifname_, fmt::format("poll failed: {}", ready.error()));
        }
    }
}

bool PcapLink::link_up() const { return impl_->interface.running(); }

}  // namespace ecpair::link
