// Batched I/O of the master: every copy a cycle sends leaves in one
// send_batch per link, in the order the cycle built them, and with
// receive_in_cycle the cycle takes the returned copies from the links itself
// (no receive thread). The segment is ecsim's Segment, driven by the test
// between cycles, so every step is deterministic.

#include <array>
#include <vector>

#include <catch2/catch.hpp>

#include "ecpair/eni/loader.hpp"
#include "ecpair/link/frame_batch.hpp"
#include "ecpair/link/memory_link.hpp"
#include "ecpair/master/master.hpp"
#include "ecpair/sim/eni_generator.hpp"
#include "ecpair/sim/segment.hpp"
#include "ecpair/wire/frame.hpp"
#include "ecpair/wire/source_mac.hpp"

using namespace ecpair;

namespace {

wire::MacAddress mac(std::uint8_t last) { return {{0x02, 0x00, 0x00, 0x00, 0x00, last}}; }

std::shared_ptr<const eni::EniConfig> generated(std::uint32_t slaves) {
    sim::GeneratedEniOptions options;
    options.slaves = slaves;
    options.input_bytes = 76;
    options.output_bytes = 76;
    return eni::load_eni_string(sim::generate_eni(options), "generated.xml").value();
}

// A master with cable redundancy on two MemoryWires whose far ends the test
// carries through a Segment when it likes.
class BatchedRing {
public:
    explicit BatchedRing(std::uint32_t slaves, bool receive_in_cycle = true)
        : eni_(generated(slaves)),
          segment_(std::move(sim::Segment::from_eni(*eni_).value())),
          main_(link::MemoryWire::make_pair("m-main", mac(0x11), "sim-main", mac(0x21), link::MemoryWireOptions{512})),
          red_(link::MemoryWire::make_pair("m-red", mac(0x12), "sim-red", mac(0x22), link::MemoryWireOptions{512})) {
        master::MasterOptions options;
        options.cable_redundancy = true;
        options.split_lrw = true;
        options.receive_in_cycle = receive_in_cycle;
        master_ = master::Master::create(eni_, options, *main_.a, red_.a.get(), events_).value();
        master_->request_state(eni::SlaveState::Op);
    }

    void cycle() { master_->run_cycle(link::Clock::now()); }

    // What the master sent on one link since the last call, taken off the wire.
    std::vector<std::vector<std::uint8_t>> take_sent(master::LinkRole role) {
        std::vector<std::vector<std::uint8_t>> frames;
        std::array<std::uint8_t, wire::kMaxFrameSizeVlan> buffer{};
        link::Link& far = role == master::LinkRole::Main ? *main_.b : *red_.b;
        while (auto frame = far.try_receive(buffer).value()) {
            frames.emplace_back(buffer.begin(), buffer.begin() + static_cast<std::ptrdiff_t>(frame->size));
        }
        return frames;
    }

    // Carries every copy the master sent through the segment and back to it.
    void carry_all() {
        for (const auto role : {master::LinkRole::Main, master::LinkRole::Red}) {
            const auto entry = role == master::LinkRole::Main ? sim::Side::Main : sim::Side::Red;
            for (auto& frame : take_sent(role)) {
                std::array<std::uint8_t, wire::kMaxFrameSizeVlan> buffer{};
                std::copy(frame.begin(), frame.end(), buffer.begin());
                std::size_t size = frame.size();
                const auto exit = segment_.carry(entry, buffer, size, 0);
                REQUIRE(exit);
                link::Link& back = *exit == sim::Side::Main ? *main_.b : *red_.b;
                REQUIRE(back.send(std::span<const std::uint8_t>(buffer.data(), size)));
            }
        }
    }

    master::Master& master() { return *master_; }
    link::MemoryLink& link(master::LinkRole role) { return role == master::LinkRole::Main ? *main_.a : *red_.a; }

private:
    std::shared_ptr<const eni::EniConfig> eni_;
    sim::Segment segment_;
    link::MemoryWire::Ends main_;
    link::MemoryWire::Ends red_;
    master::EventQueue events_{4096};
    std::unique_ptr<master::Master> master_;
};

std::uint8_t frame_id_of(const std::vector<std::uint8_t>& frame) {
    wire::MacAddress source;
    std::copy(frame.begin() + 6, frame.begin() + 12, source.bytes.begin());
    return wire::SourceMac::decode(source).frame_id;
}

}  // namespace

TEST_CASE("every copy of a cycle leaves in one batch per link, in the order built", "[master][batched_io]") {
    // 256 slaves of 76 + 76 bytes: dozens of LWR/LRD frames per cycle.
    BatchedRing ring(256);
    ring.cycle();
    const auto sent = ring.master().stats().frames_sent;
    REQUIRE(sent > 20);
    for (const auto role : {master::LinkRole::Main, master::LinkRole::Red}) {
        INFO(master::to_string(role));
        const auto counters = ring.link(role).counters();
        CHECK(counters.batches == 1);
        CHECK(counters.delivered == sent);
        const auto frames = ring.take_sent(role);
        REQUIRE(frames.size() == sent);
        for (std::size_t i = 1; i < frames.size(); ++i) {
            CHECK(static_cast<std::uint8_t>(frame_id_of(frames[i]) - frame_id_of(frames[i - 1])) == 1);
        }
    }
    ring.cycle();
    CHECK(ring.link(master::LinkRole::Main).counters().batches == 2);
    CHECK(ring.link(master::LinkRole::Red).counters().batches == 2);
}

TEST_CASE("receive in cycle: returned copies are read from the links at the next cycle", "[master][batched_io]") {
    BatchedRing ring(33);
    ring.cycle();
    ring.carry_all();
    ring.cycle();  // reads them: nothing lost, the ring is seen closed
    CHECK(ring.master().stats().frames_lost == 0);
    CHECK(ring.master().cycles_without_return() == 0);
    CHECK(ring.master().ring_state() == master::RingState::Closed);

    ring.cycle();  // nothing came back from the cycle before: every frame of it is lost
    CHECK(ring.master().stats().frames_lost > 0);
    CHECK(ring.master().cycles_without_return() == 1);
}

TEST_CASE("without receive in cycle the master leaves the links to its receive threads", "[master][batched_io]") {
    BatchedRing ring(33, /*receive_in_cycle=*/false);
    ring.cycle();
    ring.carry_all();
    ring.cycle();  // the copies wait on the links: nobody handed them to on_frame
    CHECK(ring.master().stats().frames_lost > 0);
    CHECK(ring.master().cycles_without_return() == 1);
}

namespace {

// Refuses the frame with this number (counted over all sends), takes the rest.
class RefusingLink final : public link::Link {
public:
    explicit RefusingLink(std::size_t refused) : refused_(refused) {}
    const std::string& name() const override { return name_; }
    wire::MacAddress mac() const override { return ::mac(0x31); }
    Expected<void, link::LinkError> send(ConstBytes frame) override {
        if (count_++ == refused_) return unexpected(link::LinkError{link::LinkErrc::SendFailed, "refused"});
        sent_.emplace_back(frame.begin(), frame.end());
        return {};
    }
    Expected<std::optional<link::ReceivedFrame>, link::LinkError> try_receive(Bytes) override {
        return std::optional<link::ReceivedFrame>();
    }
    Expected<std::optional<link::ReceivedFrame>, link::LinkError> receive(Bytes, std::chrono::nanoseconds) override {
        return std::optional<link::ReceivedFrame>();
    }
    int selectable_fd() const override { return 0; }
    bool link_up() const override { return true; }
    const std::vector<std::vector<std::uint8_t>>& sent() const { return sent_; }

private:
    std::string name_ = "refusing";
    std::size_t refused_;
    std::size_t count_ = 0;
    std::vector<std::vector<std::uint8_t>> sent_;
};

}  // namespace

TEST_CASE("a batch sent one by one stops at the first frame refused", "[link][batched_io]") {
    RefusingLink link(2);
    const std::array<std::uint8_t, 4> a{1}, b{2}, c{3}, d{4};
    const std::array<ConstBytes, 4> frames{ConstBytes(a), ConstBytes(b), ConstBytes(c), ConstBytes(d)};
    const auto result = link.send_batch(frames);
    CHECK(result.sent == 2);
    REQUIRE(result.error);
    CHECK(result.error->message == "refused");
    REQUIRE(link.sent().size() == 2);  // the fourth was not tried
    CHECK(link.sent()[1][0] == 2);
}

TEST_CASE("a frame batch copies frames into its slots and refuses what does not fit", "[link][batched_io]") {
    link::FrameBatch batch(2);
    std::vector<std::uint8_t> frame{1, 2, 3};
    CHECK(batch.append(frame));
    frame[0] = 9;  // the caller may reuse its buffer at once
    CHECK(batch.frames()[0][0] == 1);
    CHECK_FALSE(batch.append(std::vector<std::uint8_t>(wire::kMaxFrameSizeVlan + 1)));
    CHECK(batch.append(std::vector<std::uint8_t>(wire::kMaxFrameSizeVlan)));
    CHECK(batch.full());
    CHECK_FALSE(batch.append(frame));
    CHECK(batch.size() == 2);
    batch.clear();
    CHECK(batch.empty());
    CHECK(batch.append(frame));
    CHECK(batch.frames()[0][0] == 9);
}

TEST_CASE("a memory link sends a batch as one, dropping what a pulled cable loses", "[link][batched_io]") {
    auto ends = link::MemoryWire::make_pair("a", mac(0x41), "b", mac(0x42));
    const std::array<std::uint8_t, 60> x{7}, y{8};
    const std::array<ConstBytes, 2> frames{ConstBytes(x), ConstBytes(y)};
    CHECK(ends.a->send_batch(frames).sent == 2);
    ends.wire->set_link_up(false);
    CHECK(ends.a->send_batch(frames).sent == 2);  // as a NIC without carrier: taken, then lost
    const auto counters = ends.a->counters();
    CHECK(counters.batches == 2);
    CHECK(counters.delivered == 2);
    CHECK(counters.dropped_link_down == 2);
    std::array<std::uint8_t, 64> buffer{};
    CHECK(ends.b->try_receive(buffer).value()->size == 60);
    CHECK(buffer[0] == 7);
    CHECK(ends.b->try_receive(buffer).value()->size == 60);
    CHECK(buffer[0] == 8);
}
