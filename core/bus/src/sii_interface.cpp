#include "sii_interface.hpp"

#include <fmt/format.h>

#include "ecpair/common/bytes.hpp"
#include "ecpair/wire/esc_registers.hpp"

namespace ecpair::bus::sii_interface {

BusError error(SlaveAddress slave, const std::string& what) {
    return BusError{BusErrc::Timeout, fmt::format("SII of slave at {}: {}", slave.to_string(), what)};
}

Expected<std::uint16_t, BusError> wait_idle(BusAccess& bus, SlaveAddress slave, std::uint32_t polls) {
    for (std::uint32_t i = 0; i < polls; ++i) {
        auto status = read_register(bus, slave, wire::reg::kSiiControl, 2);
        if (!status) return unexpected(status.error());
        if (status->wkc == 0) return unexpected(error(slave, "slave does not answer"));
        const auto word = load_le<std::uint16_t>(status->data, 0);
        if ((word & kBusy) == 0) return word;
    }
    return unexpected(error(slave, "EEPROM interface stays busy"));
}

Expected<void, BusError> clear_errors(BusAccess& bus, SlaveAddress slave, std::uint16_t status) {
    if ((status & (kCommandError | kWriteEnableError)) == 0) return {};
    auto cleared = write_register(bus, slave, wire::reg::kSiiControl, {0x00, 0x00});
    if (!cleared) return unexpected(cleared.error());
    return {};
}

}  // namespace ecpair::bus::sii_interface
