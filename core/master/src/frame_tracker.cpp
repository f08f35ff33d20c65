#include "ecpair/master/frame_tracker.hpp"

#include <algorithm>

#include "ecpair/wire/frame.hpp"

namespace ecpair::master {
namespace {

// FNV-1a 64 over what a slave leaves as it is in every datagram: command,
// index byte, length and, unless slaves count it up on the way (auto-increment
// and broadcast ADP), the address; and the number of datagrams.
class SignatureHash {
public:
    template <class T>
    void add(T value) {
        for (std::size_t i = 0; i < sizeof(T); ++i) {
            hash_ ^= static_cast<std::uint8_t>(static_cast<std::uint64_t>(value) >> (8 * i));
            hash_ *= 0x100000001b3ull;
        }
    }
    std::uint64_t value() const { return hash_; }

private:
    std::uint64_t hash_ = 0xcbf29ce484222325ull;
};

template <class View>
std::uint64_t signature_of(const View& view) {
    SignatureHash hash;
    hash.add(static_cast<std::uint32_t>(view.datagram_count()));
    for (const auto d : view) {
        const auto addressing = wire::addressing_of(d.command());
        const bool slaves_count_adp =
            addressing == wire::Addressing::AutoIncrement || addressing == wire::Addressing::Broadcast;
        hash.add(static_cast<std::uint8_t>(d.command()));
        hash.add(d.index());
        hash.add(d.length());
        hash.add(slaves_count_adp ? d.address() & 0xFFFF0000u : d.address());
    }
    return hash.value();
}

}  // namespace

FrameTracker::FrameTracker(wire::NicBytes main_nic, wire::NicBytes red_nic)
    : main_nic_(main_nic), red_nic_(red_nic), slots_(256) {}

std::uint8_t FrameTracker::open(FrameKind kind, std::uint16_t index, std::uint64_t cycle, Bytes frame) {
    // Skip ids whose frame is still awaited (an acyclic frame may wait a few cycles).
    std::uint8_t id = next_id_++;
    for (int tries = 0; tries < 256 && slots_[id].sent.open; ++tries) id = next_id_++;
    Slot& slot = slots_[id];
    slot.sent = SentFrame{kind, index, cycle, true};
    ++slot.generation;
    if (auto view = wire::FrameView::parse(frame)) {
        for (const auto d : *view) d.set_index(slot.generation);
        slot.signature = signature_of(*view);
    }
    slot.sent_size = std::min(frame.size(), slot.sent_bytes.size());
    std::copy_n(frame.begin(), slot.sent_size, slot.sent_bytes.begin());
    slot.present = {false, false};
    slot.sizes = {0, 0};
    return id;
}

AcceptOutcome FrameTracker::accept(LinkRole arrived_on, ConstBytes frame) {
    auto view = wire::ConstFrameView::parse(frame);
    if (!view) return AcceptOutcome::Malformed;
    const auto source = wire::SourceMac::decode(view->ethernet().source);
    LinkRole sent_on;
    if (source.nic == main_nic_) {
        sent_on = LinkRole::Main;
    } else if (source.nic == red_nic_) {
        sent_on = LinkRole::Red;
    } else {
        return AcceptOutcome::Foreign;
    }
    Slot& slot = slots_[source.frame_id];
    if (!slot.sent.open || signature_of(*view) != slot.signature) return AcceptOutcome::Stale;
    const auto copy_index = static_cast<std::size_t>(sent_on);
    if (slot.present[copy_index]) return AcceptOutcome::Duplicate;
    const std::size_t size = std::min(frame.size(), slot.copies[copy_index].size());
    std::copy_n(frame.begin(), size, slot.copies[copy_index].begin());
    slot.sizes[copy_index] = size;
    slot.arrived_on[copy_index] = arrived_on;
    slot.present[copy_index] = true;
    return AcceptOutcome::Stored;
}

ReturnedCopy FrameTracker::copy(std::uint8_t id, LinkRole sent_on) const {
    const Slot& slot = slots_[id];
    const auto i = static_cast<std::size_t>(sent_on);
    if (!slot.present[i]) return {};
    return ReturnedCopy{ConstBytes(slot.copies[i].data(), slot.sizes[i]), classify(sent_on, slot.arrived_on[i])};
}

wire::MacAddress FrameTracker::source_mac(std::uint8_t id, LinkRole role, std::uint8_t retry_index) const {
    wire::SourceMac mac;
    mac.retry_index = retry_index;
    mac.redundancy = role == LinkRole::Red;
    mac.frame_id = id;
    mac.nic = role == LinkRole::Main ? main_nic_ : red_nic_;
    return mac.encode();
}

}  // namespace ecpair::master
