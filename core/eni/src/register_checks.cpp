// Register InitCmds whose data says something checkable: FMMU records
// (0x0600 + 16n, written whole), the station address (0x0010) and AL control
// (0x0120). What cannot be right is refused at its InitCmd, because the
// master would run on it without a word: an FMMU record that maps nothing
// sensible leaves the process data unmapped and its expected WKCs wrong.
//
// Under an <EncryptedEtherCATConfig> root the same findings mean something
// else: that format (acontis' OEM export) scrambles InitCmd data, and read
// as plain text it gives exactly such records.
//   - A station address or AL control that does not decode: the body is
//     encrypted. A master cannot address the slaves or change their state
//     with it, so the file is refused as encrypted, saying what to do.
//   - Only FMMU records that do not decode (the Murrelektronik export in
//     tests/data/eni: every other InitCmd reads as plain text): the file
//     loads, with a warning at each such record, and what depends on those
//     records is refused where it is used (a split LRW whose <Cnt> the FMMU
//     records do not give, cyclic_plan.cpp).

#include <fmt/format.h>

#include "ecpair/common/bytes.hpp"
#include "ecpair/common/hex.hpp"
#include "ecpair/common/log.hpp"
#include "ecpair/wire/esc_registers.hpp"
#include "ecpair/wire/fmmu_config.hpp"
#include "readers.hpp"

namespace ecpair::eni::detail {
namespace {

constexpr std::uint8_t kFmmuTypeBits = 0x03;        // b0 read, b1 write; the rest reserved
constexpr std::uint8_t kAlControlAck = 0x10;        // error acknowledge
constexpr std::uint8_t kAlControlIdRequest = 0x20;  // explicit device ID request

enum class ProblemKind { FmmuRecord, StationAddress, AlControl };

struct Problem {
    ProblemKind kind = ProblemKind::FmmuRecord;
    std::string what;
};

bool writes_registers(wire::Command command) {
    return command == wire::Command::Apwr || command == wire::Command::Fpwr || command == wire::Command::Bwr;
}

// Why one 16-byte FMMU record (as written, reserved bits included) cannot be right; empty when it can.
std::string fmmu_record_problem(ConstBytes record) {
    const auto start_bit = record[6];
    const auto stop_bit = record[7];
    const auto physical_bit = record[10];
    const auto type = record[11];
    const auto activate = record[12];
    if (start_bit > 7) return fmt::format("logical start bit {} (a bit is 0..7)", start_bit);
    if (stop_bit > 7) return fmt::format("logical stop bit {} (a bit is 0..7)", stop_bit);
    if (physical_bit > 7) return fmt::format("physical start bit {} (a bit is 0..7)", physical_bit);
    if ((type & ~kFmmuTypeBits) != 0) return fmt::format("type 0x{:02x} (0 unused, 1 read, 2 write, 3 both)", type);
    if (activate > 1) return fmt::format("activate 0x{:02x} (0 or 1)", activate);
    if (activate == 0) return {};
    const auto logical = load_le<std::uint32_t>(record, 0);
    const auto length = load_le<std::uint16_t>(record, 4);
    if (length == 0) return "it is active but maps 0 bytes";
    if (type == 0) return "it is active but neither reads nor writes (type 0)";
    if (std::uint64_t{logical} + length - 1 > 0xFFFFFFFFull) {
        return fmt::format("its logical range 0x{:08x} + {} bytes runs past the 4 GiB address space", logical, length);
    }
    if (length == 1 && stop_bit < start_bit) {
        return fmt::format("one byte from bit {} to bit {}: the stop bit lies before the start bit", start_bit, stop_bit);
    }
    return {};
}

// What an InitCmd's data says that cannot be right; nullopt when nothing.
// `phys_addr`: the slave's PhysAddr (nullopt for a master InitCmd).
std::optional<Problem> init_cmd_problem(const EcatCmd& cmd, std::optional<std::uint16_t> phys_addr) {
    if (!writes_registers(cmd.command)) return std::nullopt;
    const ConstBytes data(cmd.data);
    const std::uint32_t begin = cmd.ado;
    const auto end = begin + static_cast<std::uint32_t>(data.size());
    for (std::uint32_t at = wire::reg::kFmmuBase; at < wire::reg::kSmBase; at += wire::FmmuConfig::kSize) {
        if (at < begin || at + wire::FmmuConfig::kSize > end) continue;
        const auto record = data.subspan(at - begin, wire::FmmuConfig::kSize);
        const auto problem = fmmu_record_problem(record);
        if (!problem.empty()) {
            return Problem{ProblemKind::FmmuRecord,
                           fmt::format("FMMU {} record ({}) cannot be right: {}",
                                       (at - wire::reg::kFmmuBase) / wire::FmmuConfig::kSize, to_hex(record), problem)};
        }
    }
    if (phys_addr && cmd.command != wire::Command::Bwr && begin == wire::reg::kStationAddress && data.size() >= 2) {
        const auto station = load_le<std::uint16_t>(data, 0);
        if (station != *phys_addr) {
            return Problem{ProblemKind::StationAddress,
                           fmt::format("it sets station address {} but the slave's PhysAddr is {} (FPxx commands to "
                                       "{} would reach nobody)",
                                       station, *phys_addr, *phys_addr)};
        }
    }
    if (begin == wire::reg::kAlControl && !data.empty()) {
        const auto request = static_cast<std::uint8_t>(data[0] & ~(kAlControlAck | kAlControlIdRequest));
        const bool state = request == 1 || request == 2 || request == 3 || request == 4 || request == 8;
        if (!state || (data.size() >= 2 && data[1] != 0)) {
            return Problem{ProblemKind::AlControl,
                           fmt::format("it writes AL control 0x{}, which requests no state (INIT 1, PREOP 2, BOOT 3, "
                                       "SAFEOP 4, OP 8)",
                                       to_hex(data.first(std::min<std::size_t>(data.size(), 2))))};
        }
    }
    return std::nullopt;
}

struct Finding {
    Element init_cmd;
    Problem problem;
};

// The findings of one Master or Slave, in file order. read_init_cmds reads
// every <InitCmd> child, so cmds[i] came from the i-th element.
void collect(const std::vector<EcatCmd>& cmds, const Element& owner, std::optional<std::uint16_t> phys_addr,
             std::vector<Finding>& findings) {
    const auto init_cmds = owner.child("InitCmds");
    if (!init_cmds) return;
    const auto elements = init_cmds->children("InitCmd");
    for (std::size_t i = 0; i < cmds.size() && i < elements.size(); ++i) {
        if (auto problem = init_cmd_problem(cmds[i], phys_addr)) findings.push_back({elements[i], std::move(*problem)});
    }
}

}  // namespace

void check_register_init_cmds(const EniConfig& config, const Element& root, const Element& config_element,
                              const std::vector<Element>& slave_elements) {
    std::vector<Finding> findings;
    collect(config.master.init_cmds, config_element.required_child("Master"), std::nullopt, findings);
    for (std::size_t i = 0; i < config.slaves.size() && i < slave_elements.size(); ++i) {
        collect(config.slaves[i].init_cmds, slave_elements[i], config.slaves[i].info.phys_addr, findings);
    }
    if (findings.empty()) return;
    if (root.name() != "EncryptedEtherCATConfig") findings.front().init_cmd.fail(findings.front().problem.what);

    const auto version = root.attribute("EncryptionVersion");
    const auto encryption = fmt::format("<EncryptedEtherCATConfig{}>",
                                        version ? fmt::format(" EncryptionVersion=\"{}\"", *version) : std::string());
    for (const auto& finding : findings) {
        if (finding.problem.kind == ProblemKind::FmmuRecord) continue;
        finding.init_cmd.fail(fmt::format(
            "this ENI is encrypted ({}): the data of its InitCmds does not decode ({}). ecpair reads plain ENIs only: "
            "export the configuration again without encryption (an <EtherCATConfig> file), or ask its supplier for one",
            encryption, finding.problem.what));
    }
    for (const auto& finding : findings) {
        logger("eni")->warn("{}:{}: {}: {}; under {} this record is encrypted. Every other InitCmd decodes, so the file "
                            "loads, but the process data this FMMU maps cannot be relied on (export the configuration "
                            "without encryption to use it)",
                            config.source_path, finding.init_cmd.line(), finding.init_cmd.path(), finding.problem.what,
                            encryption);
    }
}

}  // namespace ecpair::eni::detail
