// EscDescription::from_eni: what an ENI slave tells about the device,
// including the SyncManager records its register InitCmds write.

#include "ecpair/sim/esc.hpp"

#include "ecpair/wire/esc_registers.hpp"
#include "ecpair/wire/fmmu_config.hpp"

namespace ecpair::sim {

namespace {

constexpr std::uint16_t kAliasRegister = 0x0012;
constexpr std::uint16_t kExplicitIdRegister = 0x0134;
constexpr std::uint16_t kProcessRam = 0x1000;

constexpr int kSmRecords = 8;

bool writes_registers(wire::Command command) {
    return command == wire::Command::Apwr || command == wire::Command::Fpwr || command == wire::Command::Bwr ||
           command == wire::Command::Aprw || command == wire::Command::Fprw;
}

// Every whole SyncManager record a write InitCmd carries (a command may
// cover several, e.g. SM0 and SM1 in 16 bytes). Records that only clear a
// SyncManager (all zero) say nothing about the device and are skipped.
void collect_sm_writes(const eni::EcatCmd& cmd, std::vector<SmInitWrite>& out) {
    if (!writes_registers(cmd.command) || cmd.ado < wire::reg::kSmBase) return;
    const std::uint32_t offset = cmd.ado - wire::reg::kSmBase;
    if (offset % wire::reg::kSmSize != 0) return;
    const bool bootstrap_only =
        cmd.transitions.contains(eni::Transition::IB) && !cmd.transitions.contains(eni::Transition::IP);
    for (std::size_t at = 0; at + wire::reg::kSmSize <= cmd.data.size(); at += wire::reg::kSmSize) {
        const auto index = static_cast<std::uint32_t>(offset / wire::reg::kSmSize + at / wire::reg::kSmSize);
        if (index >= kSmRecords) return;
        const auto config = wire::SyncManagerConfig::decode(ConstBytes(cmd.data).subspan(at, wire::reg::kSmSize));
        if (config.physical_start == 0 && config.length == 0 && config.control == 0) continue;
        out.push_back(SmInitWrite{static_cast<std::uint8_t>(index), config.physical_start, config.length, config.control,
                                  config.enabled(), bootstrap_only});
    }
}

}  // namespace

std::string_view to_string(DcSupport support) {
    switch (support) {
        case DcSupport::None: return "none";
        case DcSupport::Dc32: return "32-bit";
        case DcSupport::Dc64: return "64-bit";
    }
    return "?";
}

EscDescription EscDescription::from_eni(const eni::Slave& slave) {
    EscDescription description;
    description.name = slave.info.name;
    description.vendor_id = slave.info.vendor_id;
    description.product_code = slave.info.product_code;
    description.revision_no = slave.info.revision_no;
    description.serial_no = slave.info.serial_no.value_or(0);
    if (!slave.info.physics.empty()) description.physics = slave.info.physics;
    description.mailbox = slave.mailbox;
    description.process_data = slave.process_data;
    for (const auto& cmd : slave.init_cmds) collect_sm_writes(cmd, description.sm_init_writes);
    if (const auto& identification = slave.info.identification; identification && identification->value) {
        if (identification->ado == kAliasRegister) {
            description.alias = *identification->value;
        } else if (identification->ado == kExplicitIdRegister) {
            description.id_selector = *identification->value;
        } else if (identification->ado >= kProcessRam) {
            description.input_word_id = EscDescription::InputWord{identification->ado, *identification->value};
        }
    }
    return description;
}

}  // namespace ecpair::sim
