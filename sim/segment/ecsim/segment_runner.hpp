#pragma once
// ecsim's event loop: one thread, blocked in poll() on
//   - the MAIN and RED links (the frames waiting on a side are read and
//     carried through the segment one by one; those leaving by each side
//     are sent together, one Link::send_batch per side, before the loop
//     reads the other side),
//   - the link state sources (carrier changes -> Segment::set_side_link),
//   - the control socket (listener and clients),
//   - a stop descriptor (a signalfd for SIGINT/SIGTERM in ecsim; any
//     readable fd, e.g. an eventfd, in tests).
//   - a timeout: the earliest SM watchdog deadline of the ESCs (the slaves
//     notice a master that fell silent without any frame arriving).
// Each side's interface shows the carrier a master would see from a real
// slave: when the PHY at the slave end of that cable is gone (the slave
// facing the interface is powered off, or that cable is cut with `break`),
// the runner takes its own end of the cable down (RunnerSetup::set_carrier;
// a veth's carrier follows its peer's administrative state), and up again
// when the PHY is back. It only ever raises what it took down itself.
// With --pcap every frame in and out is recorded; the file is flushed at
// most a second after a frame and at exit. `impair` requests on the control
// socket impair either cable (CableImpairment): damaged and duplicated
// frames, and frames held back a while before they enter the segment. A
// frame damaged on its way in is counted by the port of the first slave it
// reaches (and as forwarded by the ports after it); one damaged on its way
// out is lost at the master's NIC.
//
// The runner works on the Link / LinkStateSource interfaces, so tests drive
// it over MemoryWires as ecsim drives it over PcapLinks.

#include <array>
#include <chrono>
#include <deque>
#include <span>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "cable_impairment.hpp"
#include "control_server.hpp"
#include "ecpair/common/expected.hpp"
#include "ecpair/link/frame_batch.hpp"
#include "ecpair/link/link.hpp"
#include "ecpair/link/link_state_source.hpp"
#include "ecpair/sim/pcap_recorder.hpp"
#include "ecpair/sim/segment.hpp"
#include "exit_status.hpp"

namespace ecpair::ecsim {

struct RunnerSetup {
    sim::Segment segment;
    std::unique_ptr<link::Link> main_link;
    std::unique_ptr<link::Link> red_link;  // null: no RED interface (the RED side has no carrier)
    std::vector<std::unique_ptr<link::LinkStateSource>> link_states;
    std::optional<sim::PcapRecorder> pcap;
    std::filesystem::path control_path;
    int stop_fd = -1;  // readable: leave run(); not owned
    // Sets the carrier of a side's interface as the master sees it (ecsim:
    // its own end administratively down or up); true when it changed it
    // (an interface already down is left to whoever took it down). Null:
    // the interfaces are left alone, and frames sent towards a dead PHY
    // just vanish.
    std::function<Expected<bool, std::string>(sim::Side side, bool up)> set_carrier;
};

class SegmentRunner {
public:
    // Opens the control socket; fails when it cannot.
    static Expected<std::unique_ptr<SegmentRunner>, std::string> create(RunnerSetup setup);
    ~SegmentRunner();
    SegmentRunner(const SegmentRunner&) = delete;
    SegmentRunner& operator=(const SegmentRunner&) = delete;

    // Serves until the stop descriptor is readable (returns kExitOk) or a
    // link or poll() fails (kExitFailure); the pcap file is flushed either way.
    int run();

private:
    explicit SegmentRunner(RunnerSetup setup);

    int serve();  // the loop of run()
    link::Link* link_of(sim::Side side) const;
    // Reads the frames waiting on one side's link and carries each through.
    // False when the link failed.
    bool serve_side(sim::Side side);
    // Carries one frame received on `side` through the segment and sends it on.
    void carry(sim::Side side, std::span<std::uint8_t> buffer, std::size_t size, std::uint64_t time_ns,
               sim::FrameCondition condition);
    // Queues a frame leaving by `exit` (sent by send_queued()).
    void send(sim::Side exit, std::span<const std::uint8_t> frame);
    void send_queued();
    void send_queued(sim::Side exit);
    void on_send_failure(link::Link& out, sim::Side exit, const std::string& reason);
    // Carries the delayed frames whose time has come.
    void release_delayed();
    std::string handle_control(std::string_view line);
    int poll_timeout_ms() const;
    void apply_link_changes(link::LinkStateSource& source);
    void sync_side_links();
    // Each side's carrier after a fault: down while the PHY it faces is gone.
    void sync_carriers();

    RunnerSetup setup_;
    std::unique_ptr<ControlServer> control_;
    std::chrono::steady_clock::time_point next_flush_;
    std::uint64_t truncated_frames_ = 0;
    std::uint64_t send_failures_ = 0;
    std::array<CableImpairment, 2> impairments_{CableImpairment(1), CableImpairment(2)};  // by sim::Side
    struct Delayed {
        std::chrono::steady_clock::time_point due;
        sim::Side side;
        sim::FrameCondition condition;
        std::vector<std::uint8_t> bytes;
    };
    std::deque<Delayed> delayed_;  // in due order (one delay per side, frames in arrival order)
    std::array<link::FrameBatch, 2> outgoing_;  // by sim::Side
    std::array<bool, 2> carrier_taken_down_{false, false};  // by sim::Side: set_carrier(side, false) done
};

}  // namespace ecpair::ecsim
