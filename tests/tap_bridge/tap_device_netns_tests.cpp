// TapBridge's kernel side in a namespace of its own: the TAP device is
// created with the configured MTU, MAC and addresses, an existing
// persistent device is attached, what the kernel sends on the TAP reaches
// the channel's outbound queue and what the channel delivers reaches the
// kernel.

#include <thread>

#include <catch2/catch.hpp>

#include "ecpair/tap_bridge/tap_bridge.hpp"
#include "ecpair/wire/frame.hpp"
#include "netns.hpp"

using namespace ecpair::test;
using namespace std::chrono_literals;
using ecpair::tap_bridge::InterfaceAddress;
using ecpair::tap_bridge::TapBridge;
using ecpair::tap_bridge::TapBridgeOptions;

namespace {

TapBridgeOptions options(const std::string& name) {
    TapBridgeOptions o;
    o.name = name;
    o.addresses.push_back(InterfaceAddress::parse("10.78.0.1/24").value());
    o.addresses.push_back(InterfaceAddress::parse("fd00:78::1/64").value());
    o.mac = ecpair::wire::MacAddress::parse("02:00:00:78:00:01");
    return o;
}

// An EtherCAT frame with one DATA datagram carrying `ethernet`, as an ACTIVE partner sends it.
std::vector<std::uint8_t> data_frame(const std::vector<std::uint8_t>& ethernet) {
    using namespace ecpair::tap_bridge;
    std::vector<std::uint8_t> data(kBridgeHeaderSize + kFrameLengthPrefix + ethernet.size());
    BridgePayloadWriter writer(data);
    writer.add(ethernet);
    writer.seal(BridgeKind::Data, 0x51515151, 1, 0);
    std::array<std::uint8_t, ecpair::wire::kMaxFrameSize> buffer{};
    ecpair::wire::EthernetHeader eth;
    eth.destination = ecpair::wire::MacAddress::broadcast();
    ecpair::wire::FrameBuilder builder(buffer, eth);
    ecpair::wire::DatagramHeader h;
    h.command = ecpair::wire::Command::Nop;
    h.address = ecpair::wire::DatagramHeader::physical(0, kBridgeAdo);
    builder.append(h, data);
    const auto frame = builder.finish();
    return {frame.begin(), frame.end()};
}

template <class Condition>
bool eventually(Condition condition, std::chrono::milliseconds timeout = 5s) {
    const auto give_up = std::chrono::steady_clock::now() + timeout;
    while (!condition()) {
        if (std::chrono::steady_clock::now() > give_up) return false;
        std::this_thread::sleep_for(10ms);
    }
    return true;
}

}  // namespace

TEST_CASE("the TAP device gets its MTU, MAC and address, and frames flow both ways", "[netns][tap_bridge]") {
    TestNamespace ns("ecpt-tap");
    std::unique_ptr<TapBridge> bridge;
    {
        NamespaceScope inside(ns);
        auto opened = TapBridge::open(options("ecpt0"));
        INFO((opened ? std::string() : opened.error()));
        REQUIRE(opened);
        bridge = std::move(*opened);
    }
    bridge->start();
    CHECK(ns.exec("ip link show ecpt0 | grep -q 'mtu 1446'") == 0);
    CHECK(ns.exec("ip link show ecpt0 | grep -q '02:00:00:78:00:01'") == 0);
    CHECK(ns.exec("ip addr show ecpt0 | grep -q 'inet 10.78.0.1/24'") == 0);
    // The namespace has IPv6 off by default; an IPv6 address turns it on for the TAP.
    CHECK(ns.exec("ip -6 addr show ecpt0 | grep -q 'inet6 fd00:78::1/64'") == 0);
    const auto status = bridge->status();
    CHECK(status.name == "ecpt0");
    CHECK(status.mtu == 1446);
    CHECK(status.addresses == std::vector<std::string>{"10.78.0.1/24", "fd00:78::1/64"});

    // The kernel resolves a neighbour on the TAP: ARP requests go out of the
    // TAP and into the channel's queue for the partner.
    ns.exec("ping -c 1 -W 1 10.78.0.2 >/dev/null 2>&1 &");
    REQUIRE(eventually([&] { return bridge->channel().outbound_depth() > 0; }));

    // A frame the partner sent (an ARP request for our address) reaches the
    // kernel, which answers it through the TAP.
    std::vector<std::uint8_t> arp = {
        0xff, 0xff, 0xff, 0xff, 0xff, 0xff, 0x02, 0x00, 0x00, 0x78, 0x00, 0x02, 0x08, 0x06,  // Ethernet
        0x00, 0x01, 0x08, 0x00, 0x06, 0x04, 0x00, 0x01,                                      // ARP request
        0x02, 0x00, 0x00, 0x78, 0x00, 0x02, 10, 78, 0, 2,                                    // sender
        0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 10, 78, 0, 1};                                   // target: us
    const auto queued = bridge->channel().counters().tx_frames + bridge->channel().outbound_depth();
    bridge->channel().forwarded(ecpair::master::LinkRole::Main, data_frame(arp), true);
    CHECK(bridge->channel().counters().rx_frames == 1);
    CHECK(eventually([&] { return ns.exec("ip neigh show 10.78.0.2 | grep -q 'lladdr 02:00:00:78:00:02'") == 0; }));
    // ...and its ARP reply goes out of the TAP, towards the partner.
    CHECK(eventually([&] { return bridge->channel().outbound_depth() > queued; }));

    // A runt from the TAP side is dropped and counted.
    bridge->channel().offer({});
    CHECK(bridge->channel().counters().dropped_oversized == 1);
    bridge->stop();
}

TEST_CASE("an existing persistent TAP device is attached, and a bad name is refused", "[netns][tap_bridge]") {
    TestNamespace ns("ecpt-tap");
    REQUIRE(ns.exec("ip tuntap add dev ecpt1 mode tap") == 0);
    {
        NamespaceScope inside(ns);
        auto opened = TapBridge::open(options("ecpt1"));
        INFO((opened ? std::string() : opened.error()));
        REQUIRE(opened);
        CHECK((*opened)->status().name == "ecpt1");
        auto refused = TapBridge::open(options("a-name-far-too-long-for-linux"));
        REQUIRE_FALSE(refused);
        CHECK(refused.error().find("1..15 characters") != std::string::npos);
    }
    // Persistent: it outlives the bridge.
    CHECK(ns.exec("ip link show ecpt1 >/dev/null") == 0);
}
