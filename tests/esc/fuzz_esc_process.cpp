// Fuzz target: arbitrary bytes as a frame reaching the processing units of a
// small line of ESCs (a drive with mailbox and process data, an I/O slave, a
// coupler). The ESCs keep their state between inputs, so sequences of frames
// reach deep states (SII commands, AL transitions, mailbox traffic). The first
// input byte also toggles links and power, to mix port events in.

#include <cstddef>
#include <cstdint>
#include <vector>

#include "ecpair/sim/esc.hpp"
#include "ecpair/wire/frame.hpp"

namespace {

std::vector<ecpair::sim::Esc> make_line() {
    using namespace ecpair;
    std::vector<sim::Esc> escs;
    sim::EscDescription drive;
    drive.name = "drive";
    drive.vendor_id = 0x9A;
    eni::Mailbox mailbox;
    mailbox.send = eni::MailboxArea{0x1000, 128};
    mailbox.recv = eni::MailboxArea{0x1080, 128};
    mailbox.protocols = eni::kCoE;
    drive.mailbox = mailbox;
    eni::Pdo rx;
    rx.index = 0x1600;
    rx.sm = 2;
    rx.entries = {eni::PdoEntry{0x7000, 1, 16, "out", "UINT"}};
    eni::Pdo tx;
    tx.index = 0x1A00;
    tx.sm = 3;
    tx.entries = {eni::PdoEntry{0x6000, 1, 32, "in", "UDINT"}};
    drive.process_data.rx_pdos = {rx};
    drive.process_data.tx_pdos = {tx};
    escs.emplace_back(drive);
    sim::EscDescription io;
    io.name = "io";
    io.physics = "KK";
    escs.emplace_back(io);
    sim::EscDescription coupler;
    coupler.name = "coupler";
    coupler.physics = "YYYY";
    escs.emplace_back(coupler);
    for (auto& esc : escs) {
        esc.set_physical_link(0, true);
        esc.set_physical_link(1, true);
    }
    return escs;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    static std::vector<ecpair::sim::Esc> line = make_line();
    static std::uint64_t seq = 0;
    static std::uint64_t time_ns = 0;
    if (size == 0) return 0;

    // Byte 0: bits 0-2 pick a slave, bits 3-4 a port; bit 5 toggles that
    // link, bit 6 power-cycles the slave.
    const std::uint8_t control = data[0];
    auto& target = line[static_cast<std::size_t>(control & 0x07) % line.size()];
    const int port = (control >> 3) & 0x03;
    if ((control & 0x20) != 0) target.set_physical_link(port, !target.physical_link(port));
    if ((control & 0x40) != 0) {
        target.power_off();
        target.power_on();
    }

    std::vector<std::uint8_t> frame(data + 1, data + size);
    auto parsed = ecpair::wire::FrameView::parse(frame);
    ++seq;
    for (auto& esc : line) {
        time_ns += 250;
        esc.frame_arrived_at_port(0, time_ns, seq);
        if (parsed) {
            if (esc.process(parsed.value(), ecpair::sim::FrameContext{time_ns, seq}) ==
                ecpair::sim::EpuVerdict::Destroy) {
                break;
            }
        } else {
            esc.process_non_ethercat();
        }
    }
    return 0;
}
