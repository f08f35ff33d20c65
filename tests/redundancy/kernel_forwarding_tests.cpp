// The kernel store-and-forward program against StoreAndForward: every
// synthetic frame goes through the BPF program (BPF_PROG_TEST_RUN, nothing
// sent) and through StoreAndForward on in-memory cables with the CMF hook
// the controller sets, and both must agree on the outcome, the adapter it
// leaves by and every byte. The TAP bridge's polls answered from what a
// BridgeChannel prepared. Then the loader's errors, and the program attached
// to real veths in a namespace.
//
// The program tells the arrival link by interface index, so the two links
// are veths inside a test namespace that the test thread enters.

#include <catch2/catch.hpp>

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <optional>
#include <thread>

#include "ecpair/link/memory_link.hpp"
#include "ecpair/link/pcap_link.hpp"
#include "ecpair/redundancy/cmf_format.hpp"
#include "ecpair/redundancy/cmf_inactive.hpp"
#include "ecpair/redundancy/kernel_forwarding.hpp"
#include "ecpair/redundancy/store_and_forward.hpp"
#include "ecpair/tap_bridge/bridge_channel.hpp"
#include "ecpair/wire/esc_registers.hpp"
#include "ecpair/wire/frame.hpp"
#include "netns.hpp"

using namespace ecpair;
using ecpair::master::LinkRole;
using ecpair::redundancy::ForwardOutcome;
using ecpair::redundancy::KernelForwarding;
using ecpair::redundancy::KernelForwardingVerdict;
using ecpair::redundancy::StoreAndForward;
using Action = KernelForwardingVerdict::Action;

namespace {

using Frame = std::vector<std::uint8_t>;

wire::MacAddress mac(std::uint8_t last) { return {{0x02, 0x00, 0x00, 0x00, 0x01, last}}; }

wire::EthernetHeader ethernet(std::uint8_t byte0) {
    wire::EthernetHeader eth;
    eth.destination = wire::MacAddress::broadcast();
    eth.source = wire::MacAddress{{byte0, 0x17, 0x00, 0x11, 0x22, 0x33}};
    return eth;
}

Frame finish(wire::FrameBuilder& builder) {
    const Bytes frame = builder.finish();
    return {frame.begin(), frame.end()};
}

Frame ecat_frame(std::uint8_t byte0) {
    std::array<std::uint8_t, wire::kMaxFrameSize> buffer{};
    wire::FrameBuilder builder(buffer, ethernet(byte0));
    wire::DatagramHeader lrd;
    lrd.command = wire::Command::Lrd;
    lrd.address = 0x00010000;
    const std::array<std::uint8_t, 4> data{1, 2, 3, 4};
    REQUIRE(builder.append(lrd, data));
    return finish(builder);
}

// A NOP datagram carrying one CMF segment of `kind` (payload bytes 0xEE).
void append_cmf(wire::FrameBuilder& builder, redundancy::CmfKind kind, std::uint32_t offset, std::size_t payload,
                std::uint16_t wkc = 0) {
    wire::DatagramHeader nop;
    nop.command = wire::Command::Nop;
    nop.address = wire::DatagramHeader::physical(0, wire::reg::kMasterRedAdo);
    auto datagram = builder.append(nop, redundancy::CmfSegmentHeader::kSize + payload);
    REQUIRE(datagram);
    redundancy::CmfSegmentHeader segment;
    segment.kind = kind;
    segment.part = 0;
    segment.part_count = 4;
    segment.offset = offset;
    segment.cycle_low = 77;
    segment.encode(datagram->data());
    std::fill(datagram->data().begin() + redundancy::CmfSegmentHeader::kSize, datagram->data().end(), 0xEE);
    datagram->set_wkc(wkc);
}

// An LRD, then HEADER, MASTER_PD_IN (at pd_offset), STANDBY_STATUS and a
// MASTER_PD_OUT segment: everything the INACTIVE touches or must not.
Frame cmf_frame(std::uint8_t byte0, std::uint32_t pd_offset = 0, std::size_t pd_payload = 8) {
    std::array<std::uint8_t, wire::kMaxFrameSize> buffer{};
    wire::FrameBuilder builder(buffer, ethernet(byte0));
    wire::DatagramHeader lrd;
    lrd.command = wire::Command::Lrd;
    lrd.address = 0x00010000;
    REQUIRE(builder.append(lrd, std::array<std::uint8_t, 6>{9, 9, 9, 9, 9, 9}));
    append_cmf(builder, redundancy::CmfKind::Header, 0, redundancy::CmfHeader::kSize, 3);
    append_cmf(builder, redundancy::CmfKind::MasterPdIn, pd_offset, pd_payload);
    append_cmf(builder, redundancy::CmfKind::StandbyStatus, 0, redundancy::CmfStandbyStatus::kSize, 0x00FF);
    append_cmf(builder, redundancy::CmfKind::MasterPdOut, 0, 8, 0xFFFF);  // the WKC wraps as on a slave
    return finish(builder);
}

// A TAP bridge POLL of the ACTIVE (session 0xAAAA0001) with `size` data bytes.
Frame poll_frame(std::uint32_t sequence, std::size_t size = tap_bridge::kMaxBridgeDatagramData) {
    std::array<std::uint8_t, wire::kMaxFrameSize> buffer{};
    wire::FrameBuilder builder(buffer, ethernet(0x08));
    wire::DatagramHeader nop;
    nop.command = wire::Command::Nop;
    nop.address = wire::DatagramHeader::physical(0, tap_bridge::kBridgeAdo);
    auto datagram = builder.append(nop, size);
    REQUIRE(datagram);
    tap_bridge::BridgePayloadWriter(datagram->data()).seal(tap_bridge::BridgeKind::Poll, 0xAAAA0001, sequence, 0);
    return finish(builder);
}

// The one datagram of a bridge frame.
wire::ConstDatagramView bridge_datagram(const Frame& frame) {
    auto view = wire::ConstFrameView::parse(ConstBytes(frame));
    REQUIRE(view);
    return *view->begin();
}

Frame ip_frame(std::uint8_t n) {
    Frame f(120, n);
    f[12] = 0x08;
    f[13] = 0x00;
    return f;
}

const std::vector<std::uint8_t> kPdIn{0xA0, 0xA1, 0xA2, 0xA3, 0xA4, 0xA5, 0xA6, 0xA7, 0xA8, 0xA9};
const std::vector<std::uint8_t> kStatus{0x51, 0x52, 0x53, 0x54, 0x55, 0x56, 0x57, 0x58,
                                        0x59, 0x5A, 0x5B, 0x5C, 0x5D, 0x5E, 0x5F, 0x60};

// What StoreAndForward (with the controller's CMF hook) does to one frame.
struct UserPath {
    link::MemoryWire::Ends main = link::MemoryWire::make_pair("inactive-main", mac(1), "far-main", mac(2),
                                                              link::MemoryWireOptions{16});
    link::MemoryWire::Ends red = link::MemoryWire::make_pair("inactive-red", mac(3), "far-red", mac(4),
                                                             link::MemoryWireOptions{16});
    StoreAndForward saf{*main.a, *red.a};

    UserPath() {
        saf.set_hook([](LinkRole, wire::FrameView& frame, bool first_pass) {
            if (first_pass) redundancy::process_as_inactive(frame, kPdIn, kStatus);
        });
    }

    struct Result {
        ForwardOutcome outcome;
        std::optional<LinkRole> left_by;
        Frame frame;
    };

    Result run(LinkRole arrived_on, const Frame& frame) {
        Result r{saf.on_frame(arrived_on, frame), std::nullopt, {}};
        for (const LinkRole role : {LinkRole::Main, LinkRole::Red}) {
            std::array<std::uint8_t, wire::kMaxFrameSizeVlan> buffer{};
            auto& far = role == LinkRole::Main ? *main.b : *red.b;
            auto received = far.try_receive(buffer);
            REQUIRE(received);
            if (!received->has_value()) continue;
            r.left_by = role;
            r.frame.assign(buffer.begin(), buffer.begin() + static_cast<std::ptrdiff_t>((*received)->size));
        }
        return r;
    }
};

// Two veth pairs in a namespace the test thread is in; the program loaded for their near ends.
struct KernelPath {
    test::TestNamespace ns{"ecpkf"};
    std::optional<test::NamespaceScope> inside;
    std::unique_ptr<KernelForwarding> kernel;

    KernelPath() {
        ns.create_veth("kf-main", "kf-main-far");
        ns.create_veth("kf-red", "kf-red-far");
        inside.emplace(ns);
        auto opened = KernelForwarding::open("kf-main", "kf-red", kPdIn.size());
        INFO((opened ? std::string() : opened.error()));
        REQUIRE(opened);
        kernel = std::move(*opened);
        kernel->set_forwarding(true);
        REQUIRE(kernel->set_answer(kPdIn, kStatus));
    }

    KernelForwardingVerdict run(LinkRole arrived_on, const Frame& frame) {
        auto verdict = kernel->run_once(arrived_on, frame);
        INFO((verdict ? std::string() : verdict.error()));
        REQUIRE(verdict);
        return *verdict;
    }
};

LinkRole left_by(const Frame& frame, LinkRole arrived_on, std::uint8_t byte0_before) {
    const std::uint8_t added = static_cast<std::uint8_t>(frame.at(6) & ~byte0_before);
    if (added == 0x04) return LinkRole::Main;
    if (added == 0x80) return LinkRole::Red;
    FAIL("no forwarding bit was added to byte 0 " << int(byte0_before) << " (arrived on " << to_string(arrived_on)
                                                  << ")");
    return arrived_on;
}

// Both paths on the same frame: the same outcome, adapter and bytes.
void same_on_both(KernelPath& kernel, UserPath& user, LinkRole arrived_on, const Frame& frame) {
    const auto k = kernel.run(arrived_on, frame);
    const auto u = user.run(arrived_on, frame);
    switch (u.outcome) {
        case ForwardOutcome::Forwarded:
        case ForwardOutcome::Bounced:
            REQUIRE(k.action == Action::Redirected);
            CHECK(left_by(k.frame, arrived_on, frame.at(6)) == u.left_by);
            CHECK(k.frame == u.frame);
            break;
        case ForwardOutcome::DroppedNonEtherCat:
            CHECK(k.action == Action::Passed);  // to the host's stack, unforwarded
            CHECK_FALSE(u.left_by);
            break;
        default:
            CHECK(k.action == Action::Dropped);
            CHECK_FALSE(u.left_by);
            break;
    }
}

bool counters_equal(const redundancy::StoreAndForwardCounters& a, const redundancy::StoreAndForwardCounters& b) {
    return a.forwarded_main_to_red == b.forwarded_main_to_red && a.forwarded_red_to_main == b.forwarded_red_to_main &&
           a.bounced == b.bounced && a.dropped_circulating == b.dropped_circulating &&
           a.dropped_non_ethercat == b.dropped_non_ethercat && a.dropped_damaged == b.dropped_damaged;
}

}  // namespace

TEST_CASE("kernel path: forwarding bits, circulating drop and bounce as in user space", "[kbpf]") {
    KernelPath kernel;
    UserPath user;
    for (const LinkRole arrived_on : {LinkRole::Main, LinkRole::Red}) {
        for (const std::uint8_t byte0 : Frame{0x00, 0x02, 0x08, 0x0A, 0x04, 0x80, 0x84, 0x06, 0x88, 0x7F}) {
            INFO("arrived on " << to_string(arrived_on) << ", byte 0 " << int(byte0));
            same_on_both(kernel, user, arrived_on, ecat_frame(byte0));
        }
    }
    // The link monitor says RED is down: frames from MAIN go back out of MAIN.
    for (const bool up : {false, true}) {
        kernel.kernel->set_link_state(LinkRole::Red, up);
        user.saf.set_link_state(LinkRole::Red, up);
        for (const LinkRole arrived_on : {LinkRole::Main, LinkRole::Red}) {
            for (const std::uint8_t byte0 : Frame{0x08, 0x02, 0x04, 0x80}) {
                INFO("RED " << (up ? "up" : "down") << ", arrived on " << to_string(arrived_on) << ", byte 0 "
                            << int(byte0));
                same_on_both(kernel, user, arrived_on, ecat_frame(byte0));
            }
        }
    }
    const auto k = kernel.kernel->counters();
    CHECK(counters_equal(k, user.saf.counters()));
    CHECK(k.bounced > 0);
    CHECK(k.dropped_circulating > 0);
    CHECK(k.forwarded_main_to_red > 0);
    CHECK(k.forwarded_red_to_main > 0);
}

TEST_CASE("kernel path: non-EtherCAT and damaged frames are dropped and counted", "[kbpf]") {
    KernelPath kernel;
    UserPath user;

    Frame ipv4 = ecat_frame(0x08);
    ipv4[12] = 0x08;
    ipv4[13] = 0x00;
    same_on_both(kernel, user, LinkRole::Main, ipv4);

    Frame vlan_ipv4(ipv4.begin(), ipv4.begin() + 12);  // a VLAN tag, then IPv4
    vlan_ipv4.insert(vlan_ipv4.end(), {0x81, 0x00, 0x00, 0x05, 0x08, 0x00});
    vlan_ipv4.resize(64, 0);
    same_on_both(kernel, user, LinkRole::Red, vlan_ipv4);

    Frame vlan_ecat(ipv4.begin(), ipv4.begin() + 12);  // a VLAN-tagged EtherCAT frame is forwarded
    vlan_ecat.insert(vlan_ecat.end(), {0x81, 0x00, 0x00, 0x05});
    const Frame plain = ecat_frame(0x08);
    vlan_ecat.insert(vlan_ecat.end(), plain.begin() + 12, plain.end());
    same_on_both(kernel, user, LinkRole::Main, vlan_ecat);

    Frame wrong_type = ecat_frame(0x08);
    wrong_type[15] = static_cast<std::uint8_t>((wrong_type[15] & 0x0F) | 0x40);  // EtherCAT type 4
    same_on_both(kernel, user, LinkRole::Main, wrong_type);

    Frame overrun = ecat_frame(0x08);
    overrun[16 + 6] = 0xFF;  // the first datagram's length: 0x7FF bytes
    overrun[16 + 7] = static_cast<std::uint8_t>(overrun[16 + 7] | 0x07);
    same_on_both(kernel, user, LinkRole::Main, overrun);

    Frame more_without_next = ecat_frame(0x08);
    more_without_next.resize(16 + 12 + 4);  // the datagram says M=1, and the frame ends after it
    more_without_next[16 + 7] = static_cast<std::uint8_t>(more_without_next[16 + 7] | 0x80);
    same_on_both(kernel, user, LinkRole::Red, more_without_next);

    Frame truncated_header = ecat_frame(0x08);
    truncated_header.resize(16 + 5);
    same_on_both(kernel, user, LinkRole::Red, truncated_header);

    Frame jumbo = ecat_frame(0x08);
    jumbo.resize(wire::kMaxFrameSizeVlan + 1, 0);
    same_on_both(kernel, user, LinkRole::Main, jumbo);

    const auto k = kernel.kernel->counters();
    CHECK(counters_equal(k, user.saf.counters()));
    CHECK(k.dropped_non_ethercat == 2);
    CHECK(k.dropped_damaged == 5);
    CHECK(k.forwarded_main_to_red == 1);
}

TEST_CASE("kernel path: the INACTIVE's part of the CMF on a frame's first pass", "[kbpf]") {
    KernelPath kernel;
    UserPath user;
    SECTION("fills MASTER_PD_IN and STANDBY_STATUS, WKC +1, the other CMF datagrams +2") {
        const Frame frame = cmf_frame(0x08);
        const auto k = kernel.run(LinkRole::Main, frame);
        REQUIRE(k.action == Action::Redirected);
        auto view = wire::ConstFrameView::parse(ConstBytes(k.frame));
        REQUIRE(view);
        std::vector<std::uint16_t> wkcs;
        for (const auto d : *view) wkcs.push_back(d.wkc());
        CHECK(wkcs == std::vector<std::uint16_t>{0, 5, 1, 0x0100, 0x0001});
        const auto datagrams = std::vector<wire::ConstDatagramView>(view->begin(), view->end());
        const auto pd_in = datagrams[2].data().subspan(redundancy::CmfSegmentHeader::kSize);
        CHECK(std::equal(pd_in.begin(), pd_in.end(), kPdIn.begin()));
        const auto status = datagrams[3].data().subspan(redundancy::CmfSegmentHeader::kSize);
        CHECK(std::equal(status.begin(), status.end(), kStatus.begin()));
        CHECK(k.frame == user.run(LinkRole::Main, frame).frame);
    }
    SECTION("a section's offset places its bytes; what lies beyond the answer stays as sent") {
        for (const std::uint32_t offset : {0u, 4u, 9u, 10u, 5000u}) {
            INFO("MASTER_PD_IN offset " << offset);
            same_on_both(kernel, user, LinkRole::Red, cmf_frame(0x02, offset, 8));
        }
        same_on_both(kernel, user, LinkRole::Main, cmf_frame(0x08, 0, 1200));  // more than one copy chunk
    }
    SECTION("not on a later pass") {
        for (const std::uint8_t byte0 : Frame{0x80, 0x04}) same_on_both(kernel, user, LinkRole::Red, cmf_frame(byte0));
        const Frame back = cmf_frame(0x80);
        const auto k = kernel.run(LinkRole::Red, back);
        REQUIRE(k.action == Action::Redirected);
        CHECK(std::equal(k.frame.begin() + 7, k.frame.end(), back.begin() + 7));
    }
    SECTION("a new answer is used from the next frame on") {
        const std::vector<std::uint8_t> next(kPdIn.size(), 0x33);
        REQUIRE(kernel.kernel->set_answer(next, kStatus));
        const auto k = kernel.run(LinkRole::Main, cmf_frame(0x08));
        auto view = wire::ConstFrameView::parse(ConstBytes(k.frame));
        REQUIRE(view);
        const auto datagrams = std::vector<wire::ConstDatagramView>(view->begin(), view->end());
        const auto pd_in = datagrams[2].data().subspan(redundancy::CmfSegmentHeader::kSize);
        CHECK(std::all_of(pd_in.begin(), pd_in.end(), [](std::uint8_t b) { return b == 0x33; }));
    }
}

TEST_CASE("kernel path: the TAP bridge's polls get the answers the channel prepared, both copies the same",
          "[kbpf][tap_bridge]") {
    KernelPath kernel;
    tap_bridge::BridgeChannelOptions options;
    options.session = 0xBBBB0002;
    tap_bridge::BridgeChannel inactive(options);
    inactive.role_changed(false);
    inactive.offer(ip_frame(1));
    inactive.offer(ip_frame(2));

    // The first poll: nothing prepared yet (its size was not known).
    const Frame first = poll_frame(1);
    auto k = kernel.run(LinkRole::Main, first);
    REQUIRE(k.action == Action::Redirected);
    CHECK(bridge_datagram(k.frame).wkc() == 0);
    CHECK(std::equal(k.frame.begin() + 7, k.frame.end(), first.begin() + 7));  // as sent but the forwarding bit
    inactive.kernel_forwarded(LinkRole::Main, first, *kernel.kernel);  // as user space sees it: it prepares
    CHECK(inactive.outbound_depth() == 2);                             // still queued

    // The next poll takes the answer; its other copy gets the same bytes.
    const Frame second = poll_frame(2);
    k = kernel.run(LinkRole::Main, second);
    REQUIRE(k.action == Action::Redirected);
    const auto answer = bridge_datagram(k.frame);
    CHECK(answer.wkc() == 1);
    auto decoded = tap_bridge::decode_bridge_datagram(answer.data());
    REQUIRE(decoded);
    CHECK(decoded->header.kind == tap_bridge::BridgeKind::Answer);
    CHECK(decoded->header.session == 0xBBBB0002);
    CHECK(decoded->header.sequence == 1);
    std::vector<Frame> carried;
    decoded->for_each_frame([&](ConstBytes f) { carried.emplace_back(f.begin(), f.end()); });
    CHECK(carried == std::vector<Frame>{ip_frame(1), ip_frame(2)});
    const auto other = kernel.run(LinkRole::Red, second);
    REQUIRE(other.action == Action::Redirected);
    const auto other_answer = bridge_datagram(other.frame);
    CHECK(other_answer.wkc() == 1);
    CHECK(std::equal(other_answer.data().begin(), other_answer.data().end(), answer.data().begin(),
                     answer.data().end()));
    inactive.kernel_forwarded(LinkRole::Main, second, *kernel.kernel);
    CHECK(inactive.outbound_depth() == 0);  // taken: off the queue
    CHECK(inactive.counters().answers_given == 1);
    CHECK(inactive.counters().tx_frames == 2);

    // Then an empty answer, and a poll of another size finds none.
    k = kernel.run(LinkRole::Main, poll_frame(3));
    decoded = tap_bridge::decode_bridge_datagram(bridge_datagram(k.frame).data());
    REQUIRE(decoded);
    CHECK(decoded->header.kind == tap_bridge::BridgeKind::Answer);
    CHECK(decoded->header.frame_count == 0);
    CHECK(bridge_datagram(k.frame).wkc() == 1);
    const Frame smaller = poll_frame(4, 300);
    k = kernel.run(LinkRole::Main, smaller);
    REQUIRE(k.action == Action::Redirected);
    CHECK(bridge_datagram(k.frame).wkc() == 0);
    CHECK(std::equal(k.frame.begin() + 7, k.frame.end(), smaller.begin() + 7));
}

TEST_CASE("kernel path: the loader names what is wrong", "[kbpf]") {
    test::TestNamespace ns{"ecpkf"};
    ns.create_veth("kf-main", "kf-main-far");
    test::NamespaceScope inside(ns);
    auto missing = KernelForwarding::open("kf-main", "kf-nope", 8);
    REQUIRE_FALSE(missing);
    CHECK_THAT(missing.error(), Catch::Contains("no interface kf-nope") && Catch::Contains("RED"));

    auto too_big = KernelForwarding::open("kf-main", "kf-main-far", redundancy::kernel_forwarding_max_pd_in() + 1);
    REQUIRE_FALSE(too_big);
    CHECK_THAT(too_big.error(), Catch::Contains("master_pd_in_size"));

    // Without privileges (a child that became nobody): the kernel refuses, and says what is missing.
    int pipe_fds[2];
    REQUIRE(pipe(pipe_fds) == 0);
    const pid_t child = fork();
    REQUIRE(child >= 0);
    if (child == 0) {
        close(pipe_fds[0]);
        std::string message = "could not drop privileges";
        if (setgid(65534) == 0 && setuid(65534) == 0) {
            auto opened = KernelForwarding::open("kf-main", "kf-main-far", 8);
            message = opened ? std::string("loaded") : opened.error();
        }
        (void)!write(pipe_fds[1], message.data(), message.size());
        _exit(0);
    }
    close(pipe_fds[1]);
    std::string message;
    std::array<char, 512> buffer{};
    for (ssize_t n; (n = read(pipe_fds[0], buffer.data(), buffer.size())) > 0;) message.append(buffer.data(), static_cast<std::size_t>(n));
    close(pipe_fds[0]);
    int status = 0;
    waitpid(child, &status, 0);
    CHECK_THAT(message, Catch::Contains("refused the BPF program") && Catch::Contains("CAP_BPF"));
}

namespace {

// The first frame `link` receives within `timeout` (nullopt: none).
std::optional<Frame> receive(link::Link& link, std::chrono::milliseconds timeout = std::chrono::seconds(5)) {
    std::array<std::uint8_t, wire::kMaxFrameSizeVlan> buffer{};
    const auto give_up = std::chrono::steady_clock::now() + timeout;
    while (std::chrono::steady_clock::now() < give_up) {
        auto received = link.receive(buffer, std::chrono::milliseconds(50));
        REQUIRE(received);
        if (received->has_value()) {
            return Frame(buffer.begin(), buffer.begin() + static_cast<std::ptrdiff_t>((*received)->size));
        }
    }
    return std::nullopt;
}

}  // namespace

TEST_CASE("kernel path: attached to veths it forwards on the wire, switched off or detached it does not", "[kbpf]") {
    KernelPath kernel;
    auto far_main = link::PcapLink::open("kf-main-far");
    auto far_red = link::PcapLink::open("kf-red-far");
    REQUIRE(far_main);
    REQUIRE(far_red);
    REQUIRE(kernel.kernel->attach());
    CHECK(kernel.kernel->attached());
    const Frame frame = cmf_frame(0x08);
    REQUIRE((*far_main)->send(frame));
    const auto arrived = receive(**far_red);
    REQUIRE(arrived);
    CHECK(arrived->at(6) == 0x88);
    CHECK(*arrived == kernel.run(LinkRole::Main, frame).frame);
    CHECK(kernel.kernel->counters().forwarded_main_to_red == 2);  // the wire's frame and the test run's

    // Switched off (this master became ACTIVE): attached, and every frame stays here.
    kernel.kernel->set_forwarding(false);
    REQUIRE((*far_main)->send(frame));
    CHECK_FALSE(receive(**far_red, std::chrono::milliseconds(300)));
    CHECK(kernel.run(LinkRole::Main, frame).action == Action::Passed);
    CHECK(kernel.run(LinkRole::Main, frame).frame == frame);

    kernel.kernel->set_forwarding(true);
    kernel.kernel->detach();
    CHECK_FALSE(kernel.kernel->attached());
    REQUIRE((*far_main)->send(frame));
    CHECK_FALSE(receive(**far_red, std::chrono::milliseconds(300)));
}

TEST_CASE("kernel path: a process killed with SIGKILL leaves no program forwarding", "[kbpf]") {
    test::TestNamespace ns{"ecpkf"};
    ns.create_veth("kf-main", "kf-main-far");
    ns.create_veth("kf-red", "kf-red-far");
    test::NamespaceScope inside(ns);
    auto far_main = link::PcapLink::open("kf-main-far");
    auto far_red = link::PcapLink::open("kf-red-far");
    REQUIRE(far_main);
    REQUIRE(far_red);

    // A child (in this namespace, as ecpaird would be) attaches and waits to be killed.
    int ready[2];
    REQUIRE(pipe(ready) == 0);
    const pid_t child = fork();
    REQUIRE(child >= 0);
    if (child == 0) {
        close(ready[0]);
        auto opened = KernelForwarding::open("kf-main", "kf-red", 0);
        const bool attached = opened && (*opened)->attach();
        if (attached) (*opened)->set_forwarding(true);
        (void)!write(ready[1], attached ? "y" : "n", 1);
        for (;;) pause();
    }
    close(ready[1]);
    char answer = 0;
    REQUIRE(read(ready[0], &answer, 1) == 1);
    close(ready[0]);
    REQUIRE(answer == 'y');

    const Frame frame = ecat_frame(0x08);
    REQUIRE((*far_main)->send(frame));
    const auto forwarded = receive(**far_red);
    REQUIRE(forwarded);
    CHECK(forwarded->at(6) == 0x88);

    kill(child, SIGKILL);
    int status = 0;
    REQUIRE(waitpid(child, &status, 0) == child);
    // The kernel releases the bpf_links with the process's files; give it a bounded moment.
    bool still_forwarding = true;
    for (int attempt = 0; attempt < 50 && still_forwarding; ++attempt) {
        REQUIRE((*far_main)->send(frame));
        still_forwarding = receive(**far_red, std::chrono::milliseconds(100)).has_value();
    }
    CHECK_FALSE(still_forwarding);
}
