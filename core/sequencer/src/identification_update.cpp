#include "ecpair/sequencer/identification_update.hpp"

#include <fmt/format.h>

#include "ecpair/common/bytes.hpp"
#include "ecpair/wire/al_status.hpp"
#include "ecpair/wire/esc_registers.hpp"

namespace ecpair::sequencer {
namespace {

constexpr std::uint8_t kInitWithAck = 0x11;
constexpr std::uint8_t kInit = 0x01;

}  // namespace

Expected<std::uint16_t, std::string> reinitialise_after_identification_update(bus::BusAccess& bus, Clock& clock,
                                                                              bus::SlaveAddress slave,
                                                                              std::chrono::milliseconds timeout,
                                                                              std::stop_token stop) {
    auto asked = bus::write_register(bus, slave, wire::reg::kAlControl, {kInitWithAck, 0});
    if (!asked) return unexpected(asked.error().message);
    if (asked->wkc != 1) return unexpected(fmt::format("{}: no answer to the INIT request", slave.to_string()));
    const auto deadline = clock.now() + timeout;
    for (;;) {
        auto status = bus::read_register(bus, slave, wire::reg::kAlStatus, 2);
        if (status && status->wkc == 1 && (status->data[0] & 0x1F) == kInit) break;
        if (stop.stop_requested()) return unexpected(std::string("stopped"));
        if (clock.now() >= deadline) {
            return unexpected(fmt::format("{}: not in INIT within {} ms", slave.to_string(), timeout.count()));
        }
        clock.sleep_for(kPollInterval, stop);
    }
    auto alias = bus::read_register(bus, slave, wire::reg::kStationAlias, 2);
    if (!alias || alias->wkc != 1) return unexpected(fmt::format("{}: station alias not readable", slave.to_string()));
    return load_le<std::uint16_t>(alias->data, 0);
}

}  // namespace ecpair::sequencer
