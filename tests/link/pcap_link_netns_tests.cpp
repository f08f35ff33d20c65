// PcapLink on a veth cable inside a network namespace: frames of every size
// cross unchanged in both directions, a sender never hears itself, the MAC
// and errors are right, the BPF filter works, and an end going down (or
// away) is survived.

#include "link_netns_fixture.hpp"

using namespace std::chrono_literals;
using ecpair::link::Clock;
using ecpair::link::LinkErrc;
using ecpair::link::PcapLink;
using ecpair::link::PcapLinkOptions;
using ecpair::link::test::ethercat_frame;
using ecpair::link::test::kMainMac;
using ecpair::link::test::kPatience;
using ecpair::link::test::kSimMac;
using ecpair::link::test::receive_one;
using ecpair::link::test::VethFixture;

TEST_CASE_METHOD(VethFixture, "pcap link: frames cross both ways byte-identical, short to full size", "[link][pcap]") {
    // 29 bytes: shorter than Ethernet's minimum; veth does not pad, so it arrives as sent.
    for (const std::size_t size : {std::size_t{29}, std::size_t{60}, ecpair::wire::kMaxFrameSize}) {
        INFO("frame size " << size);
        const auto outbound = ethercat_frame(size, kMainMac, static_cast<std::uint8_t>(size));
        REQUIRE(main->send(outbound));
        CHECK(receive_one(*sim) == outbound);

        const auto inbound = ethercat_frame(size, kSimMac, static_cast<std::uint8_t>(size + 1));
        REQUIRE(sim->send(inbound));
        CHECK(receive_one(*main) == inbound);
    }
}

TEST_CASE_METHOD(VethFixture, "pcap link: a sender does not receive its own frames", "[link][pcap]") {
    const auto own = ethercat_frame(60, kMainMac, 1);
    const auto reply = ethercat_frame(60, kSimMac, 2);
    REQUIRE(main->send(own));
    CHECK(receive_one(*sim) == own);
    REQUIRE(sim->send(reply));
    // Had `main` captured its own frame, it would be first in line.
    CHECK(receive_one(*main) == reply);
    std::vector<std::uint8_t> buffer(2048);
    CHECK_FALSE(main->try_receive(buffer)->has_value());
    CHECK_FALSE(sim->try_receive(buffer)->has_value());
}

TEST_CASE_METHOD(VethFixture, "pcap link: name, MAC, link state and timestamps", "[link][pcap]") {
    CHECK(main->name() == "ecm0");
    CHECK(main->mac() == kMainMac);
    CHECK(sim->mac() == kSimMac);
    CHECK(main->link_up());
    CHECK(sim->link_up());
    CHECK(main->selectable_fd() >= 0);

    const auto frame = ethercat_frame(60, kMainMac, 3);
    const auto before = Clock::now();
    REQUIRE(main->send(frame));
    std::vector<std::uint8_t> buffer(2048);
    auto received = sim->receive(buffer, kPatience);
    REQUIRE(received);
    REQUIRE(received->has_value());
    CHECK((*received)->timestamp >= before);
    CHECK((*received)->timestamp <= Clock::now());
    CHECK((*received)->wire_size == frame.size());
    CHECK((*received)->capture_time.time_since_epoch() > std::chrono::system_clock::duration::zero());
}

TEST_CASE_METHOD(VethFixture, "pcap link: the selectable fd turns readable when a frame arrives", "[link][pcap]") {
    REQUIRE(main->send(ethercat_frame(60, kMainMac, 4)));
    pollfd entry{sim->selectable_fd(), POLLIN, 0};
    CHECK(::poll(&entry, 1, static_cast<int>(std::chrono::milliseconds(kPatience).count())) == 1);
    std::vector<std::uint8_t> buffer(2048);
    CHECK(sim->try_receive(buffer)->has_value());
}

TEST_CASE_METHOD(VethFixture, "pcap link: receive without a frame returns nothing at the timeout", "[link][pcap]") {
    std::vector<std::uint8_t> buffer(2048);
    auto received = sim->receive(buffer, 5ms);
    REQUIRE(received);
    CHECK_FALSE(received->has_value());
}

TEST_CASE_METHOD(VethFixture, "pcap link: frames larger than 1518 bytes are refused", "[link][pcap]") {
    auto refused = main->send(std::vector<std::uint8_t>(ecpair::wire::kMaxFrameSizeVlan + 1));
    REQUIRE_FALSE(refused);
    CHECK(refused.error().code == LinkErrc::FrameTooLarge);
    CHECK(refused.error().message.find("ecm0") != std::string::npos);
}

TEST_CASE_METHOD(VethFixture, "pcap link: a BPF filter keeps only matching frames", "[link][pcap]") {
    std::unique_ptr<PcapLink> filtered;
    {
        ecpair::test::NamespaceScope inside(ns);
        filtered = open_link("ecs0", PcapLinkOptions{1ms, "ether proto 0x88a4"});
    }
    auto ipv4 = ethercat_frame(60, kMainMac, 5);
    ipv4[12] = 0x08;
    ipv4[13] = 0x00;
    const auto ethercat = ethercat_frame(60, kMainMac, 6);
    REQUIRE(main->send(ipv4));
    REQUIRE(main->send(ethercat));
    CHECK(receive_one(*filtered) == ethercat);
    CHECK(receive_one(*sim) == ipv4);  // the unfiltered capture saw both
    CHECK(receive_one(*sim) == ethercat);
}

TEST_CASE_METHOD(VethFixture, "pcap link: an invalid BPF filter is an error quoting it", "[link][pcap]") {
    ecpair::test::NamespaceScope inside(ns);
    auto opened = PcapLink::open("ecs0", PcapLinkOptions{1ms, "ether proto nonsense"});
    REQUIRE_FALSE(opened);
    CHECK(opened.error().code == LinkErrc::SystemError);
    CHECK(opened.error().message.find("ecs0") != std::string::npos);
    CHECK(opened.error().message.find("ether proto nonsense") != std::string::npos);
}

TEST_CASE_METHOD(VethFixture, "pcap link: opening a missing interface names it", "[link][pcap]") {
    ecpair::test::NamespaceScope inside(ns);
    auto opened = PcapLink::open("ecnope0");
    REQUIRE_FALSE(opened);
    CHECK(opened.error().code == LinkErrc::InterfaceNotFound);
    CHECK(opened.error().message.find("ecnope0") != std::string::npos);
}

TEST_CASE_METHOD(VethFixture, "pcap link: opening needs the interface up, not its carrier", "[link][pcap]") {
    ns.set_link("ecs0", false);
    ecpair::test::NamespaceScope inside(ns);
    auto refused = PcapLink::open("ecs0");
    REQUIRE_FALSE(refused);
    CHECK(refused.error().code == LinkErrc::InterfaceDown);
    CHECK(refused.error().message.find("ecs0") != std::string::npos);

    auto without_carrier = PcapLink::open("ecm0");  // its peer is down
    REQUIRE(without_carrier);
    CHECK((*without_carrier)->mac() == kMainMac);
}

TEST_CASE_METHOD(VethFixture, "pcap link: an end going down and up again is survived", "[link][pcap]") {
    ns.set_link("ecs0", false);
    await_state({"ecm0", "ecs0"}, false);
    CHECK_FALSE(main->link_up());  // no carrier: the peer is down
    CHECK_FALSE(sim->link_up());   // administratively down

    auto refused = sim->send(ethercat_frame(60, kSimMac, 7));
    REQUIRE_FALSE(refused);
    CHECK(refused.error().code == LinkErrc::SendFailed);
    CHECK(refused.error().message.find("ecs0") != std::string::npos);
    CHECK(main->send(ethercat_frame(60, kMainMac, 8)));  // no carrier: the frame is lost, not an error

    std::vector<std::uint8_t> buffer(2048);
    for (auto* link : {main.get(), sim.get()}) {
        auto received = link->receive(buffer, 20ms);
        REQUIRE(received);
        CHECK_FALSE(received->has_value());
    }

    ns.set_link("ecs0", true);
    await_state({"ecm0", "ecs0"}, true);
    CHECK(main->link_up());
    CHECK(sim->link_up());
    const auto frame = ethercat_frame(100, kMainMac, 9);
    REQUIRE(main->send(frame));
    CHECK(receive_one(*sim) == frame);
}

TEST_CASE_METHOD(VethFixture, "pcap link: an interface that disappears leaves a working, idle link", "[link][pcap]") {
    REQUIRE(ns.exec("ip link del ecm0") == 0);  // takes its peer ecs0 along
    await_state({"ecm0", "ecs0"}, false);
    CHECK_FALSE(main->link_up());
    auto refused = main->send(ethercat_frame(60, kMainMac, 1));
    REQUIRE_FALSE(refused);
    CHECK(refused.error().code == LinkErrc::SendFailed);
    std::vector<std::uint8_t> buffer(2048);
    auto received = main->receive(buffer, 20ms);
    REQUIRE(received);
    CHECK_FALSE(received->has_value());
}

TEST_CASE("pcap link: each end opened in its own namespace", "[link][pcap]") {
    ecpair::test::TestNamespace master_side{"ecpt-link"};
    ecpair::test::TestNamespace slave_side{"ecpt-link"};
    master_side.create_veth("ecm0", "ecs0");
    master_side.move_link("ecs0", slave_side);
    std::unique_ptr<PcapLink> main;
    std::unique_ptr<PcapLink> sim;
    {
        ecpair::test::NamespaceScope inside(master_side);
        main = VethFixture::open_link("ecm0", {});
    }
    {
        ecpair::test::NamespaceScope inside(slave_side);
        sim = VethFixture::open_link("ecs0", {});
    }
    const auto frame = ethercat_frame(ecpair::wire::kMaxFrameSize, main->mac(), 11);
    REQUIRE(main->send(frame));
    CHECK(receive_one(*sim) == frame);
    const auto reply = ethercat_frame(29, sim->mac(), 12);
    REQUIRE(sim->send(reply));
    CHECK(receive_one(*main) == reply);
}

namespace {
std::vector<ecpair::ConstBytes> views_of(const std::vector<std::vector<std::uint8_t>>& frames) {
    return {frames.begin(), frames.end()};
}
}  // namespace

TEST_CASE_METHOD(VethFixture, "pcap link: a batch of 150 frames crosses in order, byte-identical", "[link][pcap][batched_io]") {
    // More than one sendmmsg chunk (64), sizes from short to full.
    std::vector<std::vector<std::uint8_t>> frames;
    for (std::size_t i = 0; i < 150; ++i) {
        frames.push_back(ethercat_frame(60 + (i * 97) % (ecpair::wire::kMaxFrameSize - 59), kMainMac,
                                        static_cast<std::uint8_t>(i)));
    }
    const auto result = main->send_batch(views_of(frames));
    CHECK_FALSE(result.error);
    REQUIRE(result.sent == frames.size());
    for (std::size_t i = 0; i < frames.size(); ++i) {
        INFO("frame " << i);
        REQUIRE(receive_one(*sim) == frames[i]);
    }
    // Sent by the batch socket, still not heard by the sender's own capture.
    std::vector<std::uint8_t> buffer(2048);
    CHECK_FALSE(main->try_receive(buffer)->has_value());
}

TEST_CASE_METHOD(VethFixture, "pcap link: a batch stops before a frame that is too large, naming it", "[link][pcap][batched_io]") {
    const std::vector<std::vector<std::uint8_t>> frames{ethercat_frame(60, kMainMac, 1), ethercat_frame(61, kMainMac, 2),
                                                        std::vector<std::uint8_t>(ecpair::wire::kMaxFrameSizeVlan + 1),
                                                        ethercat_frame(62, kMainMac, 3)};
    const auto result = main->send_batch(views_of(frames));
    CHECK(result.sent == 2);
    REQUIRE(result.error);
    CHECK(result.error->code == LinkErrc::FrameTooLarge);
    CHECK(result.error->message.find("ecm0") != std::string::npos);
    CHECK(receive_one(*sim) == frames[0]);
    CHECK(receive_one(*sim) == frames[1]);
    std::vector<std::uint8_t> buffer(2048);
    CHECK_FALSE(sim->receive(buffer, 20ms)->has_value());
}

TEST_CASE_METHOD(VethFixture, "pcap link: a batch on an interface that is down fails, and works once it is up", "[link][pcap][batched_io]") {
    const std::vector<std::vector<std::uint8_t>> frames{ethercat_frame(60, kSimMac, 1), ethercat_frame(70, kSimMac, 2)};
    ns.set_link("ecs0", false);
    await_state({"ecm0", "ecs0"}, false);
    const auto refused = sim->send_batch(views_of(frames));
    CHECK(refused.sent == 0);
    REQUIRE(refused.error);
    CHECK(refused.error->code == LinkErrc::SendFailed);
    CHECK(refused.error->message.find("ecs0") != std::string::npos);

    ns.set_link("ecs0", true);
    await_state({"ecm0", "ecs0"}, true);
    const auto result = sim->send_batch(views_of(frames));
    CHECK_FALSE(result.error);
    CHECK(result.sent == 2);
    CHECK(receive_one(*main) == frames[0]);
    CHECK(receive_one(*main) == frames[1]);
}
