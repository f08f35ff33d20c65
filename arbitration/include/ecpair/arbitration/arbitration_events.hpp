#pragma once
// Arbitration's events (docs/ARBITRATION.md): a collision with another
// master and how its round chose the wait, and how a round or the start-up
// listening settled. The Supervisor raises them from the Arbiter's results.

#include <cstdint>

#include "ecpair/master/event.hpp"

namespace ecpair::arbitration::events {

extern const master::EventType kCollision;            // a = round, b = backoff in µs, c = BackoffKind, d = DecidedBy
// a = ArbitrationOutcome, b = our epoch, c = slaves we reach, d = slaves the other reaches (0xFFFF unknown)
extern const master::EventType kArbitrationSettled;

}  // namespace ecpair::arbitration::events

namespace ecpair::arbitration {

enum class ArbitrationOutcome : std::uint8_t {
    TookBusAfterListening,  // start-up: no ACTIVE heard
    YieldedToActive,        // start-up or backoff: an ACTIVE was heard
    KeptBusAfterCollision,  // backoff over in silence: this master owns the bus
};

}  // namespace ecpair::arbitration
