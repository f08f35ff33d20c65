// Arbitration's event texts: what the round decided, by which rule, and
// what this master does now (backs off, defers, takes or keeps the bus).

#include "ecpair/arbitration/arbitration_events.hpp"

#include <fmt/format.h>

#include "ecpair/arbitration/arbiter.hpp"
#include "ecpair/arbitration/contender.hpp"

namespace ecpair::arbitration {
namespace {

using master::Event;
using master::EventDescriber;

std::string_view rule_text(std::uint32_t code) {
    switch (static_cast<DecidedBy>(code)) {
        case DecidedBy::SlavesReached: return "the master that reaches more slaves keeps the bus";
        case DecidedBy::Epoch: return "same reach: the master that has owned the bus longer (older epoch) keeps it";
        case DecidedBy::Mac: return "same reach and epoch: the lower MAIN MAC keeps the bus";
        case DecidedBy::Nothing: break;
    }
    return "";
}

std::string collision(const Event& e, const EventDescriber&) {
    const auto backoff = fmt::format("{:.1f} ms", static_cast<double>(e.b) / 1000.0);
    const auto start = fmt::format("collision: another master sends on this bus (round {}); stopped sending, ", e.a);
    switch (static_cast<BackoffKind>(e.c)) {
        case BackoffKind::Random: return start + fmt::format("backing off {} (random) before listening", backoff);
        case BackoffKind::Preferred:
            return start + fmt::format("backing off {}: this master is preferred ({})", backoff, rule_text(e.d));
        case BackoffKind::Deferring:
            return start + fmt::format("deferring {}: the other master is preferred ({})", backoff, rule_text(e.d));
    }
    return "collision";
}

std::string arbitration_settled(const Event& e, const EventDescriber&) {
    const auto theirs = e.d == 0xFFFF ? std::string("unknown") : std::to_string(e.d);
    switch (static_cast<ArbitrationOutcome>(e.a)) {
        case ArbitrationOutcome::TookBusAfterListening:
            return fmt::format("arbitration: no ACTIVE master heard while listening: this master takes the bus (epoch {})",
                               e.b);
        case ArbitrationOutcome::YieldedToActive:
            return fmt::format("arbitration: an ACTIVE master is heard (it reaches {} slaves, this one {}): standing by "
                               "as INACTIVE",
                               theirs, e.c);
        case ArbitrationOutcome::KeptBusAfterCollision:
            return fmt::format("arbitration: backoff over in silence: this master owns the bus (epoch {}, reaches {} "
                               "slaves, the other {})",
                               e.b, e.c, theirs);
    }
    return "arbitration settled";
}

}  // namespace

namespace events {

constinit const master::EventType kCollision{"collision", collision};
constinit const master::EventType kArbitrationSettled{"arbitration-settled", arbitration_settled};

}  // namespace events
}  // namespace ecpair::arbitration
