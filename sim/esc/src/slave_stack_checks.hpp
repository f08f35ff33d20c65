#pragma once
// What the emulated slave stack checks before it enters a state, as SOES
// does (ESC_checkmbx, ESC_checkSM23, ESC_load_device_id):
//
//  - mailbox: SM0 and SM1 must have the start, length and control byte the
//    SII advertises (standard or bootstrap areas) and be enabled;
//  - process data: every Outputs/Inputs SyncManager whose expected size is
//    known (PDOs assigned to it in the description) must be enabled with
//    exactly that length; one expecting 0 bytes may also be left disabled.
//    SyncManagers without assigned PDOs accept any configuration;
//  - device ID: the ID selector (a rotary switch) when it is non-zero, else
//    the station alias, like SOES without a get_device_id hook;
//  - refusals: the ETG.1020 race (legacy_id_selector.hpp) refuses SAFEOP
//    with 0x0061; a slave told to refuse states from S up answers 0x0001
//    (unspecified error), the way a stuck application does.

#include <cstdint>

#include "al_state_machine.hpp"
#include "esc_layout.hpp"
#include "esc_memory.hpp"
#include "legacy_id_selector.hpp"
#include "sync_manager.hpp"

namespace ecpair::sim {

class SlaveStackChecks final : public AlChecks {
public:
    SlaveStackChecks(const EscLayout& layout, const SyncManagerUnit& sync_managers, const EscMemory& memory);

    void set_id_selector(std::uint16_t value) { id_selector_ = value; }
    // Refuse every state from `lowest` up (0: refuse nothing), as a stuck application would.
    void refuse_from(std::uint8_t lowest) { refuse_from_ = lowest; }
    void set_legacy(const LegacyIdSelector* legacy) { legacy_ = legacy; }

    std::uint16_t mailbox_error(bool bootstrap) const override;
    bool bootstrap_supported() const override { return layout_.bootstrap.has_value(); }
    bool has_mailbox() const override { return layout_.has_mailbox(); }
    std::uint16_t process_data_error() const override;
    std::uint16_t device_id() const override;
    std::uint16_t entry_refusal(AlState target) const override;

private:
    const EscLayout& layout_;
    const SyncManagerUnit& sync_managers_;
    const EscMemory& memory_;
    std::uint16_t id_selector_ = 0;
    std::uint8_t refuse_from_ = 0;
    const LegacyIdSelector* legacy_ = nullptr;
};

}  // namespace ecpair::sim
