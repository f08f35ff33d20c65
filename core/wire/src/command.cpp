#include "ecpair/wire/command.hpp"

#include <array>
#include <cctype>

#include <fmt/format.h>

namespace ecpair::wire {
namespace {

constexpr std::array<std::string_view, 15> kNames = {
    "NOP", "APRD", "APWR", "APRW", "FPRD", "FPWR", "FPRW", "BRD",
    "BWR", "BRW",  "LRD",  "LWR",  "LRW",  "ARMW", "FRMW"};

}  // namespace

bool is_known(Command command) {
    return static_cast<std::uint8_t>(command) < kNames.size();
}

Addressing addressing_of(Command command) {
    switch (command) {
        case Command::Nop: return Addressing::None;
        case Command::Aprd:
        case Command::Apwr:
        case Command::Aprw:
        case Command::Armw: return Addressing::AutoIncrement;
        case Command::Fprd:
        case Command::Fpwr:
        case Command::Fprw:
        case Command::Frmw: return Addressing::Configured;
        case Command::Brd:
        case Command::Bwr:
        case Command::Brw: return Addressing::Broadcast;
        case Command::Lrd:
        case Command::Lwr:
        case Command::Lrw: return Addressing::Logical;
    }
    return Addressing::Unknown;
}

bool command_reads(Command command) {
    switch (command) {
        case Command::Aprd:
        case Command::Aprw:
        case Command::Fprd:
        case Command::Fprw:
        case Command::Brd:
        case Command::Brw:
        case Command::Lrd:
        case Command::Lrw:
        case Command::Armw:
        case Command::Frmw: return true;
        default: return false;
    }
}

bool command_writes(Command command) {
    switch (command) {
        case Command::Apwr:
        case Command::Aprw:
        case Command::Fpwr:
        case Command::Fprw:
        case Command::Bwr:
        case Command::Brw:
        case Command::Lwr:
        case Command::Lrw:
        case Command::Armw:
        case Command::Frmw: return true;
        default: return false;
    }
}

std::string to_string(Command command) {
    if (is_known(command)) return std::string(kNames[static_cast<std::uint8_t>(command)]);
    return fmt::format("CMD(0x{:02x})", static_cast<std::uint8_t>(command));
}

bool parse_command(std::string_view name, Command& out) {
    for (std::size_t i = 0; i < kNames.size(); ++i) {
        const auto known = kNames[i];
        if (known.size() != name.size()) continue;
        bool equal = true;
        for (std::size_t k = 0; k < name.size(); ++k) {
            if (std::toupper(static_cast<unsigned char>(name[k])) != known[k]) {
                equal = false;
                break;
            }
        }
        if (equal) {
            out = static_cast<Command>(i);
            return true;
        }
    }
    return false;
}

}  // namespace ecpair::wire
