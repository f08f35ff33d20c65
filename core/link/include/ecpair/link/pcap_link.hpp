#pragma once
// A Link on a real network interface through libpcap.
//
// The capture is opened in immediate mode (each frame is handed over as soon
// as it arrives, no batching), promiscuous (EtherCAT frames go to broadcast
// or to other stations' addresses), non-blocking, and inbound only
// (PCAP_D_IN): a frame this link sends is never received back by it.
// Blocking receives sleep in poll() on pcap's selectable fd.
//
// Batches (send_batch) leave through a second AF_PACKET socket bound to the
// interface, by sendmmsg: up to 64 frames per system call. libpcap has no
// batch send, and a plain packet socket needs nothing of a ring for a few
// dozen frames a cycle (PACKET_TX_RING would need its slots polled back and
// AF_XDP a driver; veth and every NIC take sendmmsg). The socket receives
// nothing (protocol 0), and the capture is inbound only, so neither socket
// hears the other's frames.
//
// Opening needs the interface administratively up (libpcap refuses it
// otherwise: InterfaceDown); a missing carrier is fine.
//
// Namespaces: the interface is looked up in the network namespace of the
// thread that calls open(); the sockets opened there stay bound to it, so the
// link may be used from any thread afterwards.
//
// Timestamps: ReceivedFrame::timestamp is the steady clock read when the
// frame is taken from the capture ring; ReceivedFrame::capture_time is the
// kernel's (wall-clock) receive time from the pcap header.
//
// An interface that goes down while open does not break the link: send()
// fails with SendFailed naming the reason, receives return no frame, and the
// link works again once the interface is back up.

#include <chrono>
#include <memory>
#include <optional>
#include <string>

#include "ecpair/link/link.hpp"

namespace ecpair::link {

struct PcapLinkOptions {
    // pcap's buffer timeout. In immediate mode it only bounds how long the
    // kernel may hold a frame back; it never makes a call block.
    std::chrono::milliseconds pcap_timeout{1};
    // A BPF filter expression applied in the kernel, e.g. "ether proto 0x88a4".
    // Unset: every inbound frame is received.
    std::optional<std::string> bpf_filter;
};

class PcapLink final : public Link {
public:
    static Expected<std::unique_ptr<PcapLink>, LinkError> open(const std::string& ifname,
                                                               const PcapLinkOptions& options = {});
    ~PcapLink() override;

    const std::string& name() const override { return ifname_; }
    wire::MacAddress mac() const override { return mac_; }
    Expected<void, LinkError> send(ConstBytes frame) override;
    BatchSendResult send_batch(std::span<const ConstBytes> frames) override;
    Expected<std::optional<ReceivedFrame>, LinkError> try_receive(Bytes buffer) override;
    Expected<std::optional<ReceivedFrame>, LinkError> receive(Bytes buffer, std::chrono::nanoseconds timeout) override;
    int selectable_fd() const override { return selectable_fd_; }
    bool link_up() const override;

private:
    struct Impl;
    PcapLink(std::string ifname, wire::MacAddress mac, std::unique_ptr<Impl> impl, int selectable_fd);

    std::string ifname_;
    wire::MacAddress mac_;
    std::unique_ptr<Impl> impl_;
    int selectable_fd_;
};

}  // namespace ecpair::link
