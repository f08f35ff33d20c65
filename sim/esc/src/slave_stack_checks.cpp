// Compares the live SyncManager configuration (as the master wrote it) with
// the layout derived from the description.

#include "slave_stack_checks.hpp"

#include "ecpair/wire/esc_registers.hpp"

namespace ecpair::sim {
namespace {

constexpr std::uint16_t kUnspecifiedError = 0x0001;

bool matches(const SmChannel& channel, const eni::MailboxArea& area, std::uint8_t control) {
    return channel.start == area.start && channel.length == area.length && channel.control == control && channel.enabled;
}

}  // namespace

SlaveStackChecks::SlaveStackChecks(const EscLayout& layout, const SyncManagerUnit& sync_managers, const EscMemory& memory)
    : layout_(layout), sync_managers_(sync_managers), memory_(memory) {}

std::uint16_t SlaveStackChecks::mailbox_error(bool bootstrap) const {
    const auto& areas = bootstrap ? layout_.bootstrap : layout_.mailbox;
    if (!areas) return al_code::kNone;
    const bool ok = matches(sync_managers_.channel(0), areas->out, layout_.sms[0].control) &&
                    matches(sync_managers_.channel(1), areas->in, layout_.sms[1].control);
    if (ok) return al_code::kNone;
    return bootstrap ? al_code::kInvalidBootstrapMailbox : al_code::kInvalidMailbox;
}

std::uint16_t SlaveStackChecks::process_data_error() const {
    for (int n = 0; n < EscLayout::kSmCount; ++n) {
        const SmPlan& plan = layout_.sms[static_cast<std::size_t>(n)];
        if ((plan.role != SmRole::Outputs && plan.role != SmRole::Inputs) || !plan.expected_size) continue;
        const SmChannel& channel = sync_managers_.channel(n);
        const bool ok = *plan.expected_size == 0 ? (!channel.enabled || channel.length == 0)
                                                 : (channel.enabled && channel.length == *plan.expected_size);
        if (!ok) return plan.role == SmRole::Outputs ? al_code::kInvalidOutputs : al_code::kInvalidInputs;
    }
    return al_code::kNone;
}

std::uint16_t SlaveStackChecks::device_id() const {
    return id_selector_ != 0 ? id_selector_ : memory_.load<std::uint16_t>(wire::reg::kStationAlias);
}

std::uint16_t SlaveStackChecks::entry_refusal(AlState target) const {
    if (legacy_) {
        if (const std::uint16_t code = legacy_->refusal(target); code != 0) return code;
    }
    if (refuse_from_ != 0 && static_cast<std::uint8_t>(target) >= refuse_from_) return kUnspecifiedError;
    return 0;
}

}  // namespace ecpair::sim
