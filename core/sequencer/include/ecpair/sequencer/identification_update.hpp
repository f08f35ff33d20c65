#pragma once
// ETG.1020's answer to a rotary switch that raced the SII alias
// (hot-connect.md §10): the slave refuses SAFEOP with AL status code 0x0061
// "device identification value updated" and expects the master to go through
// INIT, after which it proceeds with the switch value in its station alias.
// The master recovers by itself: INIT with error acknowledge, wait for INIT,
// read the station alias now in 0x0012 (to identify the slave by it), and the
// caller runs the slave's INIT -> PREOP -> SAFEOP again.

#include <chrono>
#include <cstdint>
#include <stop_token>
#include <string>

#include "ecpair/bus/bus_access.hpp"
#include "ecpair/common/expected.hpp"
#include "ecpair/sequencer/clock.hpp"
#include "ecpair/sequencer/init_cmd_runner.hpp"

namespace ecpair::sequencer {

inline constexpr std::uint16_t kIdentificationUpdated = 0x0061;

// Whether an InitCmd failed because the slave updated its identification value.
inline bool is_identification_update(const InitCmdError& error) {
    return error.al_status_code && *error.al_status_code == kIdentificationUpdated;
}

// Takes the slave to INIT and returns its station alias; an error says what did not work.
Expected<std::uint16_t, std::string> reinitialise_after_identification_update(
    bus::BusAccess& bus, Clock& clock, bus::SlaveAddress slave, std::chrono::milliseconds timeout,
    std::stop_token stop = {});

}  // namespace ecpair::sequencer
