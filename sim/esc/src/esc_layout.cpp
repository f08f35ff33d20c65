// Built in passes: the mailbox areas from <Mailbox>, then the ENI's <SmN>
// entries on top (they may describe the mailbox SMs too), then the
// SyncManager records of the InitCmds, then the derived values (assigned
// PDOs and expected sizes, enable flags, RAM size, device emulation).

#include "esc_layout.hpp"

#include <algorithm>

#include "register_map.hpp"

namespace ecpair::sim {
namespace {

constexpr std::size_t kMinRam = 8 * 1024;
constexpr std::size_t kMaxRam = 60 * 1024;

SmRole role_of(eni::SmType type) {
    switch (type) {
        case eni::SmType::MailboxOut: return SmRole::MailboxOut;
        case eni::SmType::MailboxIn: return SmRole::MailboxIn;
        case eni::SmType::Outputs: return SmRole::Outputs;
        case eni::SmType::Inputs: return SmRole::Inputs;
        case eni::SmType::Unused: break;
    }
    return SmRole::Unused;
}

bool is_process_data(SmRole role) { return role == SmRole::Outputs || role == SmRole::Inputs; }

bool truthy(const std::string& text) { return text == "1" || text == "true" || text == "True" || text == "TRUE"; }

const eni::Pdo* find_pdo(const std::vector<eni::Pdo>& pdos, std::uint16_t index) {
    const auto it = std::find_if(pdos.begin(), pdos.end(), [&](const eni::Pdo& p) { return p.index == index; });
    return it == pdos.end() ? nullptr : &*it;
}

// PDOs assigned to a SyncManager: by their Sm attribute first, then by the
// Pdo lists of the <SmN> entries.
std::vector<AssignedPdo> assigned_pdos(const eni::ProcessData& process_data) {
    std::vector<AssignedPdo> assigned;
    const auto already = [&](const eni::Pdo* pdo) {
        return std::any_of(assigned.begin(), assigned.end(), [&](const AssignedPdo& a) { return a.pdo == pdo; });
    };
    for (const bool inputs : {false, true}) {
        for (const auto& pdo : inputs ? process_data.tx_pdos : process_data.rx_pdos) {
            if (pdo.sm && *pdo.sm < EscLayout::kSmCount) assigned.push_back({&pdo, *pdo.sm, inputs});
        }
    }
    for (const auto& sm : process_data.sync_managers) {
        if (sm.index >= EscLayout::kSmCount) continue;
        const bool inputs_first = sm.type == eni::SmType::Inputs;
        for (const std::uint16_t index : sm.pdos) {
            const eni::Pdo* pdo = find_pdo(inputs_first ? process_data.tx_pdos : process_data.rx_pdos, index);
            bool inputs = inputs_first;
            if (pdo == nullptr) {
                pdo = find_pdo(inputs_first ? process_data.rx_pdos : process_data.tx_pdos, index);
                inputs = !inputs_first;
            }
            if (pdo != nullptr && !already(pdo)) assigned.push_back({pdo, sm.index, inputs});
        }
    }
    return assigned;
}

// What the InitCmds write wins over what the ENI describes elsewhere (see
// the header). Mailbox records also give the mailbox areas; records written
// only for INIT -> BOOT give the bootstrap mailbox.
void apply_init_cmd_writes(EscLayout& layout, const std::vector<SmInitWrite>& writes,
                           std::array<std::optional<bool>, EscLayout::kSmCount>& enable) {
    std::optional<eni::MailboxArea> bootstrap_out;
    std::optional<eni::MailboxArea> bootstrap_in;
    for (const SmInitWrite& w : writes) {
        if (w.index >= EscLayout::kSmCount) continue;
        const bool mailbox_mode = (w.control & 0x03) == 0x02;
        const bool ecat_writes = (w.control & 0x0C) == 0x04;
        if (w.bootstrap) {
            if (mailbox_mode && w.index == 0) bootstrap_out = eni::MailboxArea{w.start, w.length};
            if (mailbox_mode && w.index == 1) bootstrap_in = eni::MailboxArea{w.start, w.length};
            continue;
        }
        SmPlan& plan = layout.sms[w.index];
        plan.role = mailbox_mode ? (ecat_writes ? SmRole::MailboxOut : SmRole::MailboxIn)
                                 : (ecat_writes ? SmRole::Outputs : SmRole::Inputs);
        plan.start = w.start;
        plan.control = w.control;
        plan.length = w.length;
        enable[w.index] = w.enable;
    }
    const SmPlan& out = layout.sms[0];
    const SmPlan& in = layout.sms[1];
    if (out.role == SmRole::MailboxOut && in.role == SmRole::MailboxIn && out.length > 0 && in.length > 0) {
        layout.mailbox = MailboxAreas{{out.start, out.length}, {in.start, in.length}};
    }
    if (bootstrap_out && bootstrap_in) layout.bootstrap = MailboxAreas{*bootstrap_out, *bootstrap_in};
}

// A buffer the ESC's digital I/O PDI serves by itself: outputs drive the
// pins from 0x0F00-0x0F03, inputs are sampled into 0x1000-0x1003.
bool is_digital_io(const SmPlan& plan) {
    const std::uint32_t end = std::uint32_t{plan.start} + std::max<std::uint16_t>(plan.length, 1);
    if (plan.role == SmRole::Outputs) return plan.start >= 0x0F00 && end <= 0x0F04;
    if (plan.role == SmRole::Inputs) return plan.start >= regs::kProcessRam && end <= regs::kProcessRam + 4U;
    return false;
}

}  // namespace

std::uint8_t default_sm_control(SmRole role) {
    switch (role) {
        case SmRole::MailboxOut: return 0x26;  // mailbox, ECAT writes, PDI IRQ
        case SmRole::MailboxIn: return 0x22;   // mailbox, ECAT reads, PDI IRQ
        case SmRole::Outputs: return 0x64;     // buffered, ECAT writes, PDI IRQ, watchdog
        case SmRole::Inputs: return 0x20;      // buffered, ECAT reads, PDI IRQ
        case SmRole::Unused: break;
    }
    return 0x00;
}

EscLayout EscLayout::of(const EscDescription& description) {
    EscLayout layout;

    const std::string physics = description.physics.empty() ? std::string("YY") : description.physics;
    layout.port_count = static_cast<int>(std::min<std::size_t>(physics.size(), 4));
    for (int p = 0; p < layout.port_count; ++p) {
        layout.port_physics[static_cast<std::size_t>(p)] = physics[static_cast<std::size_t>(p)] == 'K' ? 'K' : 'Y';
    }

    if (description.mailbox) {
        const eni::Mailbox& mailbox = *description.mailbox;
        if (mailbox.send && mailbox.recv) layout.mailbox = MailboxAreas{*mailbox.send, *mailbox.recv};
        if (mailbox.bootstrap_send && mailbox.bootstrap_recv) {
            layout.bootstrap = MailboxAreas{*mailbox.bootstrap_send, *mailbox.bootstrap_recv};
        }
        layout.mailbox_protocols = mailbox.protocols;
        // A mailbox with CoE init commands speaks CoE even when no <Protocol> says so.
        if (layout.mailbox_protocols == 0 && !mailbox.coe_init_cmds.empty()) layout.mailbox_protocols = eni::kCoE;
        layout.mailbox_data_link_layer = truthy(mailbox.data_link_layer);
    }
    if (layout.mailbox) {
        layout.sms[0] = SmPlan{SmRole::MailboxOut, layout.mailbox->out.start, layout.mailbox->out.length,
                               default_sm_control(SmRole::MailboxOut), true, std::nullopt};
        layout.sms[1] = SmPlan{SmRole::MailboxIn, layout.mailbox->in.start, layout.mailbox->in.length,
                               default_sm_control(SmRole::MailboxIn), true, std::nullopt};
    }

    // Enable flags the ENI states; the others follow the final length.
    std::array<std::optional<bool>, kSmCount> enable{};
    for (const auto& sm : description.process_data.sync_managers) {
        const SmRole role = role_of(sm.type);
        if (sm.index >= kSmCount || role == SmRole::Unused) continue;
        SmPlan& plan = layout.sms[sm.index];
        const bool same_role = plan.role == role;
        plan.role = role;
        if (sm.start_address) plan.start = *sm.start_address;
        plan.control = sm.control_byte.value_or(same_role ? plan.control : default_sm_control(role));
        if (sm.default_size) plan.length = *sm.default_size;
        enable[sm.index] = sm.enable;
    }
    apply_init_cmd_writes(layout, description.sm_init_writes, enable);

    layout.pdos = assigned_pdos(description.process_data);
    for (int n = 0; n < kSmCount; ++n) {
        SmPlan& plan = layout.sms[static_cast<std::size_t>(n)];
        if (!is_process_data(plan.role)) continue;
        std::uint32_t bits = 0;
        bool any = false;
        for (const AssignedPdo& a : layout.pdos) {
            if (a.sm != n) continue;
            any = true;
            for (const auto& entry : a.pdo->entries) bits += entry.bit_length;
        }
        if (any) {
            plan.expected_size = static_cast<std::uint16_t>((bits + 7) / 8);
            plan.length = *plan.expected_size;
        }
    }
    for (int n = 0; n < kSmCount; ++n) {
        SmPlan& plan = layout.sms[static_cast<std::size_t>(n)];
        if (plan.role != SmRole::Unused) plan.enable = enable[static_cast<std::size_t>(n)].value_or(plan.length > 0);
    }
    if (!layout.mailbox && layout.sms[0].role == SmRole::MailboxOut && layout.sms[1].role == SmRole::MailboxIn &&
        layout.sms[0].length > 0 && layout.sms[1].length > 0) {
        layout.mailbox = MailboxAreas{{layout.sms[0].start, layout.sms[0].length}, {layout.sms[1].start, layout.sms[1].length}};
    }

    std::optional<int> first_outputs;
    std::optional<int> first_inputs;
    std::uint32_t needed_end = regs::kProcessRam;
    bool only_digital_io = true;
    bool any_process_data = false;
    for (int n = 0; n < kSmCount; ++n) {
        const SmPlan& plan = layout.sms[static_cast<std::size_t>(n)];
        if (plan.role == SmRole::Unused) continue;
        layout.described_sm_count = n + 1;
        const bool buffered = (plan.control & 0x03) == 0x00;
        needed_end = std::max<std::uint32_t>(needed_end, plan.start + plan.length * (buffered ? 3U : 1U));
        if (plan.role == SmRole::Outputs && !first_outputs) first_outputs = n;
        if (plan.role == SmRole::Inputs && !first_inputs) first_inputs = n;
        only_digital_io = only_digital_io && is_digital_io(plan);
        any_process_data = any_process_data || is_process_data(plan.role);
    }
    layout.output_sm = first_outputs.value_or(2);
    layout.input_sm = first_inputs.value_or(3);
    for (const auto& areas : {layout.mailbox, layout.bootstrap}) {
        if (!areas) continue;
        needed_end = std::max<std::uint32_t>(needed_end, areas->out.start + std::uint32_t{areas->out.length});
        needed_end = std::max<std::uint32_t>(needed_end, areas->in.start + std::uint32_t{areas->in.length});
    }
    const std::size_t needed_ram = ((needed_end - regs::kProcessRam) + 1023) / 1024 * 1024;
    layout.ram_bytes = std::clamp(needed_ram, kMinRam, kMaxRam);
    layout.device_emulation = !layout.mailbox && !layout.bootstrap && any_process_data && only_digital_io;
    return layout;
}

std::uint8_t EscLayout::port_descriptor() const {
    std::uint8_t descriptor = 0;
    for (int p = 0; p < 4; ++p) {
        const char physics = port_physics[static_cast<std::size_t>(p)];
        const std::uint8_t code = physics == 'Y' ? 0x3 : physics == 'K' ? 0x2 : 0x0;
        descriptor = static_cast<std::uint8_t>(descriptor | (code << (2 * p)));
    }
    return descriptor;
}

}  // namespace ecpair::sim
