// The pair as design.md §1 draws it, in one process: the ACTIVE's MAIN and
// RED are test-driven MemoryLinks, the slaves an ecsim Segment, the INACTIVE
// a StoreAndForward. The four values of source MAC byte 0 that design.md §2
// lists must be seen where it says:
//
//   0x08 at the INACTIVE's MAIN   (ACTIVE's RED copy, straight over the master-master cable)
//   0x88 at the ACTIVE's MAIN     (the same, forwarded out of the INACTIVE's RED, back through the slaves)
//   0x02 at the INACTIVE's RED    (ACTIVE's MAIN copy, processed by the slaves)
//   0x06 at the ACTIVE's RED      (the same, forwarded out of the INACTIVE's MAIN)

#include <catch2/catch.hpp>

#include <map>

#include "ecpair/link/memory_link.hpp"
#include "ecpair/redundancy/store_and_forward.hpp"
#include "ecpair/sim/segment.hpp"
#include "ecpair/wire/esc_registers.hpp"
#include "ecpair/wire/frame.hpp"
#include "ecpair/wire/source_mac.hpp"

using namespace ecpair;
using ecpair::master::LinkRole;
using ecpair::redundancy::StoreAndForward;

namespace {

constexpr std::size_t kSlaves = 3;
constexpr wire::NicBytes kActiveMainNic{{0x00, 0x00, 0x11}};
constexpr wire::NicBytes kActiveRedNic{{0x00, 0x00, 0x12}};

wire::MacAddress mac(std::uint8_t last) { return {{0x02, 0x00, 0x00, 0x00, 0x00, last}}; }

sim::Segment three_slaves() {
    std::vector<sim::SlaveSpec> specs;
    for (std::size_t i = 1; i <= kSlaves; ++i) {
        sim::EscDescription esc;
        esc.name = "S" + std::to_string(i);
        esc.vendor_id = 2;
        esc.product_code = 0x07D83052;
        specs.push_back(sim::SlaveSpec{esc, static_cast<std::uint16_t>(1000 + i), std::nullopt, 0});
    }
    return std::move(sim::Segment::from_specs(std::move(specs)).value());
}

// One BRD of AL status: every slave that processes it adds 1 to the WKC.
std::vector<std::uint8_t> active_frame(LinkRole sent_on, std::uint8_t frame_id) {
    wire::SourceMac source;
    source.redundancy = sent_on == LinkRole::Red;
    source.frame_id = frame_id;
    source.nic = sent_on == LinkRole::Main ? kActiveMainNic : kActiveRedNic;
    wire::EthernetHeader eth;
    eth.destination = wire::MacAddress::broadcast();
    eth.source = source.encode();
    std::array<std::uint8_t, wire::kMaxFrameSize> buffer{};
    wire::FrameBuilder builder(buffer, eth);
    wire::DatagramHeader brd;
    brd.command = wire::Command::Brd;
    brd.address = wire::DatagramHeader::physical(0, wire::reg::kAlStatus);
    (void)builder.append(brd, 2);
    const Bytes frame = builder.finish();
    return {frame.begin(), frame.end()};
}

enum class Place { InactiveMain, InactiveRed, ActiveMain, ActiveRed };

struct Seen {
    std::uint8_t byte0 = 0;
    std::uint16_t wkc = 0;
};

// design.md §1: ACTIVE MAIN -- slaves -- INACTIVE RED; INACTIVE MAIN -- ACTIVE RED.
class PairRing {
public:
    PairRing() : saf_(*master_cable_.a, *inactive_red_.b) {}

    StoreAndForward& inactive() { return saf_; }
    link::MemoryWire& master_master_cable() { return *master_cable_.wire; }

    void active_sends(LinkRole role, const std::vector<std::uint8_t>& frame) {
        REQUIRE((role == LinkRole::Main ? *active_main_.a : *master_cable_.b).send(frame));
    }

    // Moves frames until none is in flight; records every frame that reached a master's NIC.
    std::multimap<Place, Seen> run() {
        std::multimap<Place, Seen> seen;
        for (bool moved = true; moved;) {
            moved = false;
            std::size_t size = 0;
            // Into the segment at either side, out at whichever side the ESCs send it.
            link::Link* sides[2] = {active_main_.b.get(), inactive_red_.a.get()};
            for (std::size_t s = 0; s < 2; ++s) {
                while (receive(*sides[s], size)) {
                    moved = true;
                    const auto exit = segment_.carry(static_cast<sim::Side>(s), buffer_, size, now_ns_ += 1000);
                    if (exit) REQUIRE(sides[static_cast<std::size_t>(*exit)]->send(ConstBytes(buffer_.data(), size)));
                }
            }
            // The INACTIVE: seen at its NIC, then stored and forwarded.
            while (receive(*master_cable_.a, size)) {
                moved = true;
                seen.emplace(Place::InactiveMain, observe(size));
                saf_.on_frame(LinkRole::Main, ConstBytes(buffer_.data(), size));
            }
            while (receive(*inactive_red_.b, size)) {
                moved = true;
                seen.emplace(Place::InactiveRed, observe(size));
                saf_.on_frame(LinkRole::Red, ConstBytes(buffer_.data(), size));
            }
            // The ACTIVE only looks.
            while (receive(*active_main_.a, size)) seen.emplace(Place::ActiveMain, observe(size));
            while (receive(*master_cable_.b, size)) seen.emplace(Place::ActiveRed, observe(size));
        }
        return seen;
    }

private:
    bool receive(link::Link& link, std::size_t& size) {
        auto frame = link.try_receive(buffer_);
        REQUIRE(frame);
        if (!frame->has_value()) return false;
        size = (*frame)->size;
        return true;
    }

    Seen observe(std::size_t size) {
        auto view = wire::ConstFrameView::parse(ConstBytes(buffer_.data(), size));
        REQUIRE(view);
        return Seen{buffer_[6], (*view->begin()).wkc()};
    }

    sim::Segment segment_ = three_slaves();
    link::MemoryWire::Ends active_main_ = link::MemoryWire::make_pair("active-main", mac(0x11), "seg-main", mac(0x21));
    link::MemoryWire::Ends inactive_red_ = link::MemoryWire::make_pair("seg-red", mac(0x22), "inactive-red", mac(0x32));
    link::MemoryWire::Ends master_cable_ =
        link::MemoryWire::make_pair("inactive-main", mac(0x31), "active-red", mac(0x12));
    StoreAndForward saf_;
    std::array<std::uint8_t, wire::kMaxFrameSizeVlan> buffer_{};
    std::uint64_t now_ns_ = 1'000'000;
};

std::vector<std::pair<std::uint8_t, std::uint16_t>> at(const std::multimap<Place, Seen>& seen, Place place) {
    std::vector<std::pair<std::uint8_t, std::uint16_t>> values;
    for (auto [it, end] = seen.equal_range(place); it != end; ++it) values.emplace_back(it->second.byte0, it->second.wkc);
    return values;
}

using Values = std::vector<std::pair<std::uint8_t, std::uint16_t>>;

}  // namespace

TEST_CASE("byte 0 in a healthy ring is 0x08, 0x88, 0x02, 0x06 where design.md says", "[redundancy][saf][ring]") {
    PairRing ring;
    ring.active_sends(LinkRole::Main, active_frame(LinkRole::Main, 1));
    ring.active_sends(LinkRole::Red, active_frame(LinkRole::Red, 1));
    const auto seen = ring.run();

    // (byte 0, WKC): only the MAIN copy is processed by the slaves.
    CHECK(at(seen, Place::InactiveMain) == Values{{0x08, 0}});
    CHECK(at(seen, Place::ActiveMain) == Values{{0x88, 0}});
    CHECK(at(seen, Place::InactiveRed) == Values{{0x02, kSlaves}});
    CHECK(at(seen, Place::ActiveRed) == Values{{0x06, kSlaves}});
    CHECK(ring.inactive().counters().forwarded_main_to_red == 1);
    CHECK(ring.inactive().counters().forwarded_red_to_main == 1);
}

TEST_CASE("with the master-master cable broken, the MAIN copy returns to the ACTIVE's MAIN", "[redundancy][saf][ring]") {
    PairRing ring;
    ring.master_master_cable().set_link_up(false);
    ring.inactive().set_link_state(LinkRole::Main, false);
    ring.active_sends(LinkRole::Main, active_frame(LinkRole::Main, 2));
    ring.active_sends(LinkRole::Red, active_frame(LinkRole::Red, 2));  // lost on the broken cable
    const auto seen = ring.run();

    CHECK(at(seen, Place::InactiveMain).empty());
    CHECK(at(seen, Place::InactiveRed) == Values{{0x02, kSlaves}});
    // Bounced out of the INACTIVE's RED, back through the slaves unprocessed: processed once.
    CHECK(at(seen, Place::ActiveMain) == Values{{0x82, kSlaves}});
    CHECK(at(seen, Place::ActiveRed).empty());
    CHECK(ring.inactive().counters().bounced == 1);
}
