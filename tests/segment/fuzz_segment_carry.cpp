// Fuzz target for ecsim's frame path: whatever bytes arrive on a side are
// carried through a small tree segment (a 4-port coupler with a branch on
// port D, then a line), never crashing, never hanging, and always leaving the
// frame's length alone except for the padding to 60 bytes. The segment lives
// across inputs, so frames that rewrite ESC registers (loop settings, AL
// control...) change what later inputs meet.
//
// Input: byte 0 picks the entry side (bit 0) and a fault that holds while
// this frame travels (bits 1-3: none, break, power off, MAIN carrier down,
// RED carrier down, an unknown slave spliced in, a port error, none; bits
// 4-7: the slave or link it concerns, bits 6-7 also the port of a port
// error); the rest is the frame. Faults are undone after each input so that
// the wiring does not drift into a dead segment; a port error no frame
// reached stays pending for the next inputs.
//
// Every input goes through two such segments, one with the fast pass and one
// where every ESC processes every frame: the frames, exits and every ESC's
// memory (but DC's system time copy, see fast_pass_test.cpp) must agree.

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <cstdlib>

#include "ecpair/common/log.hpp"
#include "ecpair/sim/segment.hpp"
#include "ecpair/wire/constants.hpp"

namespace {

using ecpair::sim::Side;

ecpair::sim::Segment make_segment(bool fast_pass) {
    ecpair::set_log_level("warn");  // faults are logged at info: thousands of lines otherwise
    auto slave = [](const char* name, const char* physics) {
        ecpair::sim::EscDescription description;
        description.name = name;
        description.vendor_id = 2;
        description.product_code = 0x044C2C52;
        description.physics = physics;
        return description;
    };
    std::vector<ecpair::sim::SlaveSpec> specs{
        {slave("coupler", "YYYY"), 1001, std::nullopt, 0},
        {slave("branch", "YY"), 1002, ecpair::eni::PreviousPort{true, 'D', 1001}, 0},
        {slave("line 1", "YY"), 1003, ecpair::eni::PreviousPort{true, 'B', 1001}, 0},
        {slave("line 2", "YY"), 1004, std::nullopt, 0},
    };
    ecpair::sim::SegmentOptions options;
    options.fast_pass = fast_pass;
    auto segment = ecpair::sim::Segment::from_specs(std::move(specs), options);
    if (!segment) std::abort();
    return std::move(segment).value();
}

enum class Fault : std::uint8_t { None, Break, PowerOff, MainDown, RedDown, UnknownSlave, PortError };

struct AppliedFault {
    Fault fault = Fault::None;
    std::size_t target = 0;
};

AppliedFault apply_fault(ecpair::sim::Segment& segment, std::uint8_t selector) {
    const std::size_t link = static_cast<std::size_t>(selector >> 4) % (segment.slave_count() + 1);
    const std::size_t position = link == 0 ? 1 : link;
    switch ((selector >> 1) & 0x07) {
        case 1: (void)segment.break_link_after(link); return {Fault::Break, link};
        case 2: (void)segment.power_off(position); return {Fault::PowerOff, position};
        case 3: segment.set_side_link(Side::Main, false); return {Fault::MainDown, 0};
        case 4: segment.set_side_link(Side::Red, false); return {Fault::RedDown, 0};
        case 5: (void)segment.insert_unknown_slave(position); return {Fault::UnknownSlave, position};
        case 6: (void)segment.inject_rx_errors(position, selector >> 6, 1); return {Fault::PortError, position};
        default: return {};
    }
}

void undo(ecpair::sim::Segment& segment, const AppliedFault& applied) {
    switch (applied.fault) {
        case Fault::Break: (void)segment.repair_link_after(applied.target); break;
        case Fault::PowerOff: (void)segment.power_on(applied.target); break;
        case Fault::MainDown: segment.set_side_link(Side::Main, true); break;
        case Fault::RedDown: segment.set_side_link(Side::Red, true); break;
        case Fault::UnknownSlave: (void)segment.remove_unknown_slave(applied.target); break;
        case Fault::PortError:
        case Fault::None: break;
    }
}

// Every byte of every ESC (the DC registers a read computes are written only
// by frames that address the ESC, alike in both), and the ESCs' clocks.
bool same_escs(const ecpair::sim::Segment& a, const ecpair::sim::Segment& b, std::uint64_t now_ns) {
    for (std::size_t position = 1; position <= a.slave_count(); ++position) {
        if (a.slave(position).read_memory(0, 0x10000) != b.slave(position).read_memory(0, 0x10000)) return false;
        if (a.slave(position).dc_system_time_at(now_ns) != b.slave(position).dc_system_time_at(now_ns)) return false;
    }
    return true;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    static ecpair::sim::Segment segment = make_segment(true);
    static ecpair::sim::Segment reference = make_segment(false);
    static std::uint64_t now_ns = 0;
    if (size == 0) return 0;

    const AppliedFault fault = apply_fault(segment, data[0]);
    apply_fault(reference, data[0]);
    const Side entry = (data[0] & 1) != 0 ? Side::Red : Side::Main;
    std::array<std::uint8_t, ecpair::wire::kMaxFrameSizeVlan> buffer{};
    const std::size_t length = std::min(size - 1, buffer.size());
    std::copy_n(data + 1, length, buffer.begin());
    std::size_t frame_size = length;
    auto reference_buffer = buffer;
    std::size_t reference_size = length;
    now_ns += 1'000'000;
    const auto exit = segment.carry(entry, buffer, frame_size, now_ns);
    const auto reference_exit = reference.carry(entry, reference_buffer, reference_size, now_ns);
    undo(segment, fault);
    undo(reference, fault);
    if (exit != reference_exit || buffer != reference_buffer || !same_escs(segment, reference, now_ns)) std::abort();
    if (frame_size != std::max(length, ecpair::wire::kMinFrameSize)) std::abort();
    if (segment.slave_count() != 4) std::abort();

    // Every frame that came in went out or is counted as dead.
    const auto& c = segment.counters();
    const std::uint64_t in = c.sides[0].frames_in + c.sides[1].frames_in;
    const std::uint64_t out = c.sides[0].frames_out + c.sides[1].frames_out;
    const std::uint64_t dead =
        c.destroyed_circulating + c.lost_no_link + c.lost_closed_port + c.non_ethercat_dropped + c.hop_limit_exceeded +
        c.damaged_dropped;
    if (in != out + dead) std::abort();
    return 0;
}
