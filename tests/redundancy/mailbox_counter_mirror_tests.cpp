// The INACTIVE's record of the ACTIVE's mailbox counters, read from the SM0
// writes it forwards; a new ACTIVE continues after them.

#include <catch2/catch.hpp>

#include <array>

#include "ecpair/eni/loader.hpp"
#include "ecpair/sequencer/mailbox_transport.hpp"
#include "ecpair/wire/frame.hpp"
#include "ecpair/wire/mailbox.hpp"
#include "mailbox_counter_mirror.hpp"

using namespace ecpair;

namespace {

const std::string kEni = std::string(ECPAIR_TEST_ENI_DIR "/twincat_kpierczy_5slaves.xml");

// An FPWR of a slave's whole SM0 carrying a mailbox message with `counter`.
std::vector<std::uint8_t> mailbox_write(const sequencer::MailboxChannel& mailbox, std::uint8_t counter) {
    std::vector<std::uint8_t> buffer(wire::kMaxFrameSizeVlan);
    wire::EthernetHeader eth;
    eth.destination = wire::MacAddress::broadcast();
    wire::FrameBuilder builder(buffer, eth);
    wire::DatagramHeader header;
    header.command = wire::Command::Fpwr;
    header.address = wire::DatagramHeader::physical(mailbox.station, mailbox.send.start);
    auto d = builder.append(header, mailbox.send.length);
    REQUIRE(d);
    wire::MailboxHeader{10, 0, 0, 0, wire::MailboxType::CoE, counter}.encode(d->data());
    const auto frame = builder.finish();
    return {frame.begin(), frame.end()};
}

}  // namespace

TEST_CASE("the counters of the ACTIVE's mailbox writes are kept per slave", "[redundancy]") {
    const auto eni = eni::load_eni_file(kEni).value();
    redundancy::MailboxCounterMirror mirror(*eni);
    CHECK(mirror.counters() == std::vector<std::uint8_t>(eni->slaves.size(), 0));

    std::size_t with_mailbox = eni->slaves.size();
    std::optional<sequencer::MailboxChannel> channel;
    for (std::size_t i = 0; i < eni->slaves.size() && !channel; ++i) {
        channel = sequencer::mailbox_channel_of(eni->slaves[i]);
        if (channel) with_mailbox = i;
    }
    REQUIRE(channel);
    for (const std::uint8_t counter : std::array<std::uint8_t, 3>{3, 4, 5}) {
        const auto frame = mailbox_write(*channel, counter);
        mirror.observe(wire::ConstFrameView::parse(frame).value());
    }
    const auto counters = mirror.counters();
    CHECK(counters[with_mailbox] == 5);
    for (std::size_t i = 0; i < counters.size(); ++i) {
        if (i != with_mailbox) CHECK(counters[i] == 0);
    }

    // A write elsewhere (another address, or too short for a mailbox header) is not a mailbox message.
    auto other = *channel;
    other.send.start = static_cast<std::uint16_t>(other.send.start + 2);
    const auto elsewhere = mailbox_write(other, 7);
    mirror.observe(wire::ConstFrameView::parse(elsewhere).value());
    CHECK(mirror.counters()[with_mailbox] == 5);
}
