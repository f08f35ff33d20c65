// The made-up ESC InitCmds (see the header for what each transition gets).
// Every command points at the slave's line in the ENI so that an error
// message still leads to the right place.

#include "ecpair/sequencer/synthesized_init_cmds.hpp"

#include <algorithm>

#include "ecpair/common/bytes.hpp"
#include "ecpair/sequencer/mailbox_transport.hpp"
#include "ecpair/wire/al_status.hpp"
#include "ecpair/wire/esc_registers.hpp"
#include "ecpair/wire/fmmu_config.hpp"

namespace ecpair::sequencer {
namespace {

constexpr std::uint8_t kErrorAcknowledge = 0x10;
constexpr std::uint8_t kSm0DefaultControl = 0x26;  // mailbox, ECAT writes, PDI IRQ
constexpr std::uint8_t kSm1DefaultControl = 0x22;  // mailbox, ECAT reads, PDI IRQ
constexpr std::uint32_t kRetries = 3;
constexpr std::chrono::milliseconds kStateTimeout{5000};
constexpr std::chrono::milliseconds kOperationalTimeout{10000};

class Builder {
public:
    explicit Builder(const eni::Slave& slave) : slave_(slave) {}

    std::vector<eni::EcatCmd> take() { return std::move(cmds_); }

    void write(wire::Command command, std::uint16_t ado, std::vector<std::uint8_t> data, const char* comment) {
        auto& cmd = add(command, ado, comment);
        cmd.data = std::move(data);
        cmd.expected_wkc = 1;
    }

    // Request `state` in AL control, then read AL status until it shows the
    // state (and, going up, no error flag).
    void request_state(wire::Command write_cmd, std::uint8_t control, eni::SlaveState state, bool going_up,
                       const char* comment) {
        write(write_cmd, wire::reg::kAlControl, {control, 0x00}, comment);
        const auto read_cmd = write_cmd == wire::Command::Apwr ? wire::Command::Aprd : wire::Command::Fprd;
        auto& check = add(read_cmd, wire::reg::kAlStatus, "check AL status (made up)");
        check.data.assign(6, 0);
        check.expected_wkc = 1;
        eni::Validate validate;
        validate.data = {static_cast<std::uint8_t>(state), 0, 0, 0, 0, 0};
        const std::uint8_t mask = going_up ? wire::AlStatus::kStateMask | wire::AlStatus::kErrorBit
                                           : wire::AlStatus::kStateMask;
        validate.mask = {mask, 0, 0, 0, 0, 0};
        validate.timeout = state == eni::SlaveState::Safeop || state == eni::SlaveState::Op ? kOperationalTimeout
                                                                                           : kStateTimeout;
        check.validate = validate;
        check.timeout = validate.timeout;
    }

    void sync_manager(std::uint8_t index, const wire::SyncManagerConfig& config, const char* comment) {
        std::vector<std::uint8_t> data(wire::SyncManagerConfig::kSize, 0);
        config.encode(data);
        write(wire::Command::Fpwr, static_cast<std::uint16_t>(wire::reg::kSmBase + wire::reg::kSmSize * index),
              std::move(data), comment);
    }

    std::uint16_t auto_increment_address() const {
        return static_cast<std::uint16_t>(0x10000u - slave_.info.ring_position);
    }

private:
    eni::EcatCmd& add(wire::Command command, std::uint16_t ado, const char* comment) {
        eni::EcatCmd cmd;
        cmd.command = command;
        cmd.adp = wire::addressing_of(command) == wire::Addressing::AutoIncrement ? auto_increment_address()
                                                                                  : slave_.info.phys_addr;
        cmd.ado = ado;
        cmd.comment = comment;
        cmd.retries = kRetries;
        cmd.source_line = slave_.source_line;
        cmds_.push_back(std::move(cmd));
        return cmds_.back();
    }

    const eni::Slave& slave_;
    std::vector<eni::EcatCmd> cmds_;
};

std::uint8_t control_byte(const eni::Slave& slave, std::uint8_t index, std::uint8_t fallback) {
    for (const auto& sm : slave.process_data.sync_managers) {
        if (sm.index == index && sm.control_byte) return *sm.control_byte;
    }
    return fallback;
}

void init_to_preop(Builder& b, const eni::Slave& slave) {
    b.request_state(wire::Command::Apwr, static_cast<std::uint8_t>(eni::SlaveState::Init) | kErrorAcknowledge,
                    eni::SlaveState::Init, false, "set device state to INIT (made up)");
    std::vector<std::uint8_t> station(2, 0);
    store_le<std::uint16_t>(station, 0, slave.info.phys_addr);
    b.write(wire::Command::Apwr, wire::reg::kStationAddress, station, "set station address (made up)");
    if (const auto mailbox = mailbox_channel_of(slave)) {
        b.write(wire::Command::Fpwr, wire::reg::kSmBase, std::vector<std::uint8_t>(2 * wire::SyncManagerConfig::kSize, 0),
                "clear SM0/SM1 (made up)");
        wire::SyncManagerConfig sm0;
        sm0.physical_start = mailbox->send.start;
        sm0.length = mailbox->send.length;
        sm0.control = control_byte(slave, 0, kSm0DefaultControl);
        sm0.activate = 0x01;
        b.sync_manager(0, sm0, "set SM0 (mailbox out, made up)");
        wire::SyncManagerConfig sm1;
        sm1.physical_start = mailbox->recv.start;
        sm1.length = mailbox->recv.length;
        sm1.control = control_byte(slave, 1, kSm1DefaultControl);
        sm1.activate = 0x01;
        b.sync_manager(1, sm1, "set SM1 (mailbox in, made up)");
    }
    b.request_state(wire::Command::Fpwr, static_cast<std::uint8_t>(eni::SlaveState::Preop), eni::SlaveState::Preop,
                    true, "set device state to PREOP (made up)");
}

// A process-data SM's length: the bits of the PDOs assigned to it (by the
// SM's Pdo list or the PDO's Sm attribute), else its DefaultSize/MaxSize.
std::optional<std::uint16_t> process_data_size(const eni::Slave& slave, const eni::SyncManager& sm) {
    std::uint32_t bits = 0;
    bool any = false;
    for (const auto* pdos : {&slave.process_data.rx_pdos, &slave.process_data.tx_pdos}) {
        for (const auto& pdo : *pdos) {
            const bool listed = std::find(sm.pdos.begin(), sm.pdos.end(), pdo.index) != sm.pdos.end();
            if (!listed && pdo.sm != sm.index) continue;
            any = true;
            for (const auto& entry : pdo.entries) bits += entry.bit_length;
        }
    }
    if (any) return static_cast<std::uint16_t>((bits + 7) / 8);
    return sm.default_size ? sm.default_size : sm.max_size;
}

void preop_to_safeop(Builder& b, const eni::Slave& slave) {
    for (const auto& sm : slave.process_data.sync_managers) {
        if (sm.type != eni::SmType::Outputs && sm.type != eni::SmType::Inputs) continue;
        const auto size = process_data_size(slave, sm);
        if (!sm.start_address || !size) continue;
        wire::SyncManagerConfig config;
        config.physical_start = *sm.start_address;
        config.length = *size;
        config.control = sm.control_byte.value_or(sm.type == eni::SmType::Outputs ? 0x64 : 0x20);
        // Advantech writes Enable=false on SMs that have PDOs assigned; a slave
        // refuses SAFEOP with such an SM switched off, so assigned data wins.
        config.activate = *size > 0 ? 0x01 : 0x00;
        b.sync_manager(sm.index, config, "set process data SM (made up)");
    }
    b.request_state(wire::Command::Fpwr, static_cast<std::uint8_t>(eni::SlaveState::Safeop), eni::SlaveState::Safeop,
                    true, "set device state to SAFEOP (made up)");
}

}  // namespace

std::vector<eni::EcatCmd> synthesize_esc_init_cmds(const eni::Slave& slave, eni::Transition transition) {
    Builder b(slave);
    const auto down = [&b](eni::SlaveState state, const char* comment) {
        b.request_state(wire::Command::Fpwr, static_cast<std::uint8_t>(state), state, false, comment);
    };
    switch (transition) {
        case eni::Transition::IP: init_to_preop(b, slave); break;
        case eni::Transition::PS: preop_to_safeop(b, slave); break;
        case eni::Transition::SO:
            b.request_state(wire::Command::Fpwr, static_cast<std::uint8_t>(eni::SlaveState::Op), eni::SlaveState::Op,
                            true, "set device state to OP (made up)");
            break;
        case eni::Transition::OS: down(eni::SlaveState::Safeop, "set device state to SAFEOP (made up)"); break;
        case eni::Transition::OP:
        case eni::Transition::SP: down(eni::SlaveState::Preop, "set device state to PREOP (made up)"); break;
        case eni::Transition::OI:
        case eni::Transition::SI:
        case eni::Transition::PI: down(eni::SlaveState::Init, "set device state to INIT (made up)"); break;
        default: break;
    }
    return b.take();
}

}  // namespace ecpair::sequencer
