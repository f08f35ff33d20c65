#include "legacy_id_selector.hpp"

#include "ecpair/wire/esc_registers.hpp"

namespace ecpair::sim {

void LegacyIdSelector::on_power_on(EscMemory& memory, const SiiEeprom& eeprom) {
    race_ = false;
    shown_ = false;
    clear_sii_pending_ = false;
    if (selector_ == 0) return;
    const std::uint16_t sii_alias = eeprom.alias();
    memory.store<std::uint16_t>(wire::reg::kStationAlias, selector_);
    if (sii_alias == 0) {
        log_->info("{}: ID selector {} copied into the station alias", owner_, selector_);
        return;
    }
    race_ = true;
    clear_sii_pending_ = true;
    log_->warn("{}: ID selector {} and SII alias {} both set: station alias = {}, the SII alias is cleared at "
               "INIT -> PREOP and SAFEOP is refused with 0x0061 until INIT",
               owner_, selector_, sii_alias, selector_);
}

void LegacyIdSelector::after_request(AlControlWord request, AlState before, AlState after, std::uint16_t status_code,
                                     SiiEeprom& eeprom) {
    if (clear_sii_pending_ && before == AlState::Init && after == AlState::Preop) {
        clear_sii_pending_ = false;
        eeprom.set_alias(0);
        log_->info("{}: SII alias overwritten with 0 (ETG.1020 race procedure)", owner_);
    }
    if (race_ && status_code == kDeviceIdUpdated) shown_ = true;
    if (race_ && shown_ && request.requested == static_cast<std::uint8_t>(AlState::Init)) clear("INIT request");
}

std::uint16_t LegacyIdSelector::refusal(AlState target) const {
    return race_ && target == AlState::Safeop ? kDeviceIdUpdated : 0;
}

void LegacyIdSelector::reload_written() {
    if (race_) clear("reload object written");
}

void LegacyIdSelector::clear(std::string_view why) {
    race_ = false;
    shown_ = false;
    log_->info("{}: device identification error cleared ({})", owner_, why);
}

}  // namespace ecpair::sim
