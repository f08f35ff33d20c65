#pragma once
// Master-to-master IP for a redundant pair (design.md §3, issue 9): a kernel
// TAP device whose frames travel in Acyclic Master Red Frames between the
// two controllers, with no extra cable or NIC. TCP/IP between the masters
// works in either redundancy state as long as one master is ACTIVE, and
// follows the roles across a switchover or failover.
//
//   auto bridge = TapBridge::open(options);        // creates or attaches the TAP
//   controller.set_acyclic_channel(&(*bridge)->channel());
//   (*bridge)->start();                            // the TAP I/O thread
//
// The TAP's MTU is the largest IP packet whose frame fits one bridge
// datagram of one EtherCAT frame (1446 bytes with the largest poll); a
// configured MTU above that is refused, naming the number that fits.
//
// Threads: one TAP I/O thread of its own, blocked in poll() on the TAP, a
// wake-up eventfd (frames for the TAP were delivered) and a stop eventfd.
// It never touches the cycle: it exchanges frames with the cycle and
// receive threads through BridgeChannel's bounded queues.

#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <thread>
#include <vector>

#include "ecpair/common/expected.hpp"
#include "ecpair/tap_bridge/bridge_channel.hpp"
#include "ecpair/tap_bridge/interface_address.hpp"
#include "ecpair/wire/mac_address.hpp"

namespace ecpair::tap_bridge {

class TapDevice;

struct TapBridgeOptions {
    std::string name = "ecpair0";
    std::vector<InterfaceAddress> addresses;  // at most one IPv4, any number of IPv6
    std::optional<wire::MacAddress> mac;      // else the kernel's (random) one; ecpaird gives default_mac()
    std::optional<std::size_t> mtu;           // else the largest that fits
    std::size_t poll_size = kMaxBridgeDatagramData;
    std::size_t queue_frames = 256;
};

struct TapBridgeStatus {
    std::string name;
    std::vector<std::string> addresses;
    std::string mac;
    std::size_t mtu = 0;
    BridgeFlow flow;
    BridgeCounters counters;
    std::size_t outbound_depth = 0;  // our frames waiting for the partner
    std::size_t inbound_depth = 0;   // the partner's frames waiting for our TAP
    std::size_t queue_capacity = 0;
};

// A locally administered unicast MAC derived from the instance's and the
// TAP's names (02:ec + 4 bytes of their FNV-1a hash): the same at every
// start, so that the partner's neighbour cache stays right when this master
// restarts, and different for the two members of a pair.
wire::MacAddress default_mac(std::string_view instance, std::string_view tap);

class TapBridge {
public:
    // Checks the options (the MTU against what fits), then creates or attaches the TAP.
    static Expected<std::unique_ptr<TapBridge>, std::string> open(const TapBridgeOptions& options);
    // The MTU the options give, or why they are refused ("tap MTU 1500 does not fit ...: 1446 does").
    static Expected<std::size_t, std::string> mtu_for(const TapBridgeOptions& options);
    ~TapBridge();
    TapBridge(const TapBridge&) = delete;
    TapBridge& operator=(const TapBridge&) = delete;

    void start();
    void stop();

    BridgeChannel& channel() { return channel_; }
    TapBridgeStatus status() const;

private:
    TapBridge(const TapBridgeOptions& options, std::size_t mtu, std::unique_ptr<TapDevice> device, int wake_fd,
              int stop_fd, std::uint32_t session);
    void run();
    void read_tap();
    void write_tap();

    TapBridgeOptions options_;
    std::size_t mtu_;
    std::unique_ptr<TapDevice> device_;
    int wake_fd_;
    int stop_fd_;
    BridgeChannel channel_;
    std::thread thread_;
};

}  // namespace ecpair::tap_bridge
