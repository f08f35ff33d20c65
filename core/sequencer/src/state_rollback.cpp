#include "ecpair/sequencer/state_rollback.hpp"

#include <fmt/format.h>

#include "ecpair/wire/al_status.hpp"
#include "ecpair/wire/command.hpp"
#include "ecpair/wire/datagram.hpp"
#include "ecpair/wire/esc_registers.hpp"

namespace ecpair::sequencer {
namespace {

constexpr std::uint8_t kSafeop = 0x04;
constexpr std::uint8_t kOp = 0x08;

// The AL state bits of states above `state` (BOOT, 0x03, counts as below SAFEOP).
std::uint8_t states_above(std::uint8_t state) {
    return static_cast<std::uint8_t>((kSafeop | kOp) & ~((state << 1) - 1));
}

std::uint8_t al_state_of(bus::BusAccess& bus, std::uint16_t station) {
    auto status = bus::read_register(bus, bus::SlaveAddress::station(station), wire::reg::kAlStatus, 2);
    if (!status || status->wkc != 1 || status->data.empty()) return 0;
    return wire::AlStatus{status->data[0]}.state();
}

}  // namespace

Expected<std::vector<SlaveAhead>, std::string> take_back_slaves_ahead(
    bus::BusAccess& bus, Clock& clock, const std::vector<std::pair<std::size_t, std::uint16_t>>& stations,
    std::uint8_t state, std::chrono::milliseconds timeout, std::stop_token stop) {
    const std::uint8_t above = states_above(state);
    // The slaves OR their AL status into a BRD: no bit above `state`, nobody is ahead.
    bus::DatagramRequest all;
    all.command = wire::Command::Brd;
    all.address = wire::DatagramHeader::physical(0, wire::reg::kAlStatus);
    all.data.assign(2, 0);
    if (auto seen = bus.exchange(all); !seen || seen->wkc == 0 || (seen->data[0] & above) == 0) {
        return std::vector<SlaveAhead>{};  // nobody ahead, or nobody answers (the transition says why)
    }

    std::vector<SlaveAhead> ahead;
    for (const auto& [index, station] : stations) {
        const std::uint8_t now = al_state_of(bus, station);
        if ((now & above) == 0) continue;
        ahead.push_back({index, station, now});
        (void)bus::write_register(bus, bus::SlaveAddress::station(station), wire::reg::kAlControl, {state, 0});
    }
    const auto deadline = clock.now() + timeout;
    for (const auto& slave : ahead) {
        while (al_state_of(bus, slave.station) != state) {
            if (stop.stop_requested()) return unexpected(std::string("stopped"));
            if (clock.now() >= deadline) {
                return unexpected(fmt::format("station {} did not go back from {} to {} within {} ms", slave.station,
                                              wire::al_state_name(slave.state), wire::al_state_name(state),
                                              timeout.count()));
            }
            clock.sleep_for(kPollInterval, stop);
        }
    }
    return ahead;
}

}  // namespace ecpair::sequencer
