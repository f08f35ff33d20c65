#pragma once
// A transition that stopped halfway leaves slaves ahead of the master: a
// PREOP -> SAFEOP that failed at slave 12 has slaves 1-11 in SAFEOP while the
// master is still PREOP. Run again as it is, the transition would give those
// slaves their PREOP-only commands in SAFEOP (a PDO assignment is refused
// there with SDO abort 0x08000022), and every retry would fail at slave 1.
// Before an upward transition runs, the slaves above its source state are
// taken back to it. One broadcast read tells whether any slave is ahead, so a
// transition that starts cleanly costs a single datagram.

#include <chrono>
#include <cstdint>
#include <stop_token>
#include <string>
#include <utility>
#include <vector>

#include "ecpair/bus/bus_access.hpp"
#include "ecpair/common/expected.hpp"
#include "ecpair/sequencer/clock.hpp"

namespace ecpair::sequencer {

struct SlaveAhead {
    std::size_t slave_index = 0;  // into EniConfig::slaves
    std::uint16_t station = 0;
    std::uint8_t state = 0;       // the AL state it was in
};

// Takes every slave of `stations` (slave index, station address) whose AL
// state is above `state` (PREOP or SAFEOP) back to `state` and waits until it
// is there. Returns the slaves it took back; an error names the slave that
// did not follow within `timeout`.
Expected<std::vector<SlaveAhead>, std::string> take_back_slaves_ahead(
    bus::BusAccess& bus, Clock& clock, const std::vector<std::pair<std::size_t, std::uint16_t>>& stations,
    std::uint8_t state, std::chrono::milliseconds timeout, std::stop_token stop = {});

}  // namespace ecpair::sequencer
