#pragma once
// A veth cable ecm0 <-> ecs0 in a fresh namespace, both ends opened with
// PcapLink and watched by a LinkStateMonitor, all opened from inside the
// namespace (NamespaceScope) while the test itself runs outside it.

#include <poll.h>

#include <catch2/catch.hpp>
#include <chrono>
#include <memory>
#include <numeric>
#include <vector>

#include "ecpair/link/link_state_monitor.hpp"
#include "ecpair/link/pcap_link.hpp"
#include "ecpair/wire/constants.hpp"
#include "netns.hpp"

namespace ecpair::link::test {

inline const wire::MacAddress kMainMac{{0x02, 0x00, 0x00, 0x00, 0x00, 0x01}};
inline const wire::MacAddress kSimMac{{0x02, 0x00, 0x00, 0x00, 0x00, 0x02}};

// How long a test waits for something that must happen (a frame, a state
// change) before it fails. Generous: it bounds a hang, it measures nothing.
inline constexpr std::chrono::seconds kPatience{20};

// An EtherCAT-typed frame of `size` bytes from `source`, payload counting up from `seed`.
inline std::vector<std::uint8_t> ethercat_frame(std::size_t size, const wire::MacAddress& source, std::uint8_t seed) {
    std::vector<std::uint8_t> frame(size);
    std::fill_n(frame.begin(), 6, std::uint8_t{0xff});
    std::copy(source.bytes.begin(), source.bytes.end(), frame.begin() + 6);
    frame[12] = 0x88;
    frame[13] = 0xa4;
    std::iota(frame.begin() + 14, frame.end(), seed);
    return frame;
}

struct VethFixture {
    VethFixture() {
        ns.create_veth("ecm0", "ecs0");
        REQUIRE(ns.exec("ip link set ecm0 address " + kMainMac.to_string() + " && ip link set ecs0 address " +
                        kSimMac.to_string()) == 0);
        ecpair::test::NamespaceScope inside(ns);
        main = open_link("ecm0", {});
        sim = open_link("ecs0", {});
        auto opened = LinkStateMonitor::open({"ecm0", "ecs0"});
        REQUIRE(opened);
        monitor = std::move(opened).value();
    }

    static std::unique_ptr<PcapLink> open_link(const std::string& ifname, const PcapLinkOptions& options) {
        auto opened = PcapLink::open(ifname, options);
        if (!opened) FAIL("cannot open " << ifname << ": " << opened.error().message);
        return std::move(opened).value();
    }

    // Waits for the monitor until every named interface has reported `up`.
    // Returns the changes seen.
    std::vector<LinkStateChange> await_state(const std::vector<std::string>& interfaces, bool up) {
        std::vector<LinkStateChange> seen;
        const auto deadline = Clock::now() + kPatience;
        auto all_reported = [&] {
            for (const auto& name : interfaces) {
                if (monitor->is_up(name).value_or(false) != up) return false;
            }
            return true;
        };
        while (!all_reported() && Clock::now() < deadline) {
            pollfd entry{monitor->selectable_fd(), POLLIN, 0};
            ::poll(&entry, 1, 1000);
            auto changes = monitor->read_changes();
            seen.insert(seen.end(), changes.begin(), changes.end());
        }
        REQUIRE(all_reported());
        return seen;
    }

    ecpair::test::TestNamespace ns{"ecpt-link"};
    std::unique_ptr<PcapLink> main;
    std::unique_ptr<PcapLink> sim;
    std::unique_ptr<LinkStateMonitor> monitor;
};

// Receives one frame within kPatience; fails the test otherwise.
inline std::vector<std::uint8_t> receive_one(Link& link) {
    std::vector<std::uint8_t> buffer(2048);
    auto received = link.receive(buffer, kPatience);
    if (!received) FAIL(link.name() << ": " << received.error().message);
    if (!received->has_value()) FAIL(link.name() << ": no frame arrived");
    buffer.resize((*received)->size);
    return buffer;
}

}  // namespace ecpair::link::test
