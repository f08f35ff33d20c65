#pragma once
// Distributed Clocks at start-up and after a topology change, on a worker
// thread through BusAccess (the state machine's, at the end of INIT ->
// PREOP, before the cyclic frames carry the drift compensation; and
// Hot-Connect's, for slaves that join):
//   1. the slaves on the bus by position: DC unit and clock width (0x0008
//      bits 2 and 3), station address, DL status (the tree, propagation_delays.hpp);
//   2. the reference clock: the first candidate on the bus with a DC unit;
//   3. the ports that lead out of the segment (a ring's way back to the
//      master's RED side) are closed for the measurement, so that the frame
//      turns at the end of the line and comes back through every slave;
//   4. one BWR of 0x0900 latches every port's receive time; 0x0900-0x090F and
//      0x0918 are read from every DC slave; the exits are opened again;
//   5. every DC slave's delay from the reference clock (0x0928) is written
//      where it changed;
//   6. offsets (0x0920) so that every slave's system time equals the
//      reference's: at start-up for all of them (the reference's own makes
//      the system time the master's clock since 2000-01-01), after a
//      topology change only for the slaves that joined -- the running ones
//      keep their clocks, SYNC0 edges are neither moved nor lost;
//   7. static drift compensation: a burst of ARMW frames on 0x0910 at the
//      reference clock, each its own frame (the host sends them);
//   8. the reference clock's 64-bit system time, with the moment it was read,
//      for the cyclic side (master shift unwraps the ARMW's 32 bits with it).
// While it measures, the host holds the cyclic drift compensation (the
// running slaves free-wheel on their compensated clocks for a few cycles)
// and knows that frames bounce at the closed exits on purpose.

#include <chrono>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "ecpair/bus/bus_access.hpp"
#include "ecpair/common/expected.hpp"

namespace ecpair::dc {

// One slave on the bus as DC sees it, by position.
struct SlaveClock {
    std::uint16_t position = 0;
    std::uint16_t station = 0;
    bool has_dc = false;
    bool wide = false;                    // 64-bit system time
    std::optional<std::int64_t> delay;    // 0x0928 as written
    std::optional<std::uint64_t> offset;  // 0x0920 as written (or as read, for slaves that kept theirs)
    std::uint32_t difference = 0;         // 0x092C after the static drift compensation (raw)
    std::string why;                      // why it has no delay
};

struct DcSetup {
    std::uint16_t reference_position = 0;
    std::uint16_t reference_station = 0;
    std::vector<SlaveClock> slaves;                   // by position
    std::uint64_t reference_time = 0;                 // its system time (64 bit)...
    std::chrono::steady_clock::time_point read_at{};  // ...read at about this moment
    std::uint32_t static_frames = 0;                  // ARMW frames sent for the static drift compensation
};

// What DcStartup needs of the master besides the bus (MasterDcHost in core/master).
class DcHost {
public:
    virtual ~DcHost() = default;
    // Cyclic drift compensation off (true) or on again: the topology is being measured.
    virtual void hold(bool held) = 0;
    // The segment's exits are closed on purpose: a frame that comes back on
    // the port it left by is complete and no line break.
    virtual void ring_opened(bool opened) = 0;
    // Sends `frames` ARMW frames on 0x0910 at `reference_position`, each its
    // own frame, and returns once they are out (an error says why not).
    virtual Expected<void, std::string> static_drift_compensation(std::uint16_t reference_position,
                                                                  std::uint32_t frames) = 0;
    // The result, for the cyclic side and the operators.
    virtual void configured(const DcSetup& setup) = 0;
};

struct DcRequest {
    // Reference clock candidates by station address, in the order tried (DcPlan's).
    std::vector<std::uint16_t> candidates;
    // Start-up: every DC slave gets its offset, the reference the master's
    // clock. Otherwise only the slaves at these stations (Hot-Connect joiners).
    bool start_up = true;
    std::vector<std::uint16_t> joining;
    std::uint32_t static_frames = 10'000;
};

struct DcStartupOptions {
    std::chrono::milliseconds timeout{100};  // per datagram
    std::uint32_t retries = 3;
    std::function<std::chrono::steady_clock::time_point()> now = [] { return std::chrono::steady_clock::now(); };
    // The master's clock in ns since 2000-01-01 00:00 (the reference clock's offset at start-up).
    std::function<std::uint64_t()> wall_clock = [] { return ns_since_2000(std::chrono::system_clock::now()); };
    static std::uint64_t ns_since_2000(std::chrono::system_clock::time_point t);
};

class DcStartup {
public:
    DcStartup(bus::BusAccess& bus, DcHost& host, DcStartupOptions options = {});

    // Errors name what failed: no DC-capable reference ("reference clock:
    // station 1001 has no DC unit, station 1002 is not on the bus"), a bus
    // error with the register, a topology that cannot be measured.
    Expected<DcSetup, std::string> run(const DcRequest& request);

private:
    Expected<void, std::string> measure(DcSetup& setup, const DcRequest& request);

    bus::BusAccess& bus_;
    DcHost& host_;
    DcStartupOptions options_;
};

}  // namespace ecpair::dc
