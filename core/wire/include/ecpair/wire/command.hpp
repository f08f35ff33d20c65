#pragma once
// EtherCAT datagram commands (esc-facts.md §1). Unknown codes are kept as
// they are: Command is an enum over the raw byte, so a decoder never fails
// on a reserved command and an encoder writes back what it read.

#include <cstdint>
#include <string>
#include <string_view>

namespace ecpair::wire {

enum class Command : std::uint8_t {
    Nop = 0,
    Aprd = 1,
    Apwr = 2,
    Aprw = 3,
    Fprd = 4,
    Fpwr = 5,
    Fprw = 6,
    Brd = 7,
    Bwr = 8,
    Brw = 9,
    Lrd = 10,
    Lwr = 11,
    Lrw = 12,
    Armw = 13,
    Frmw = 14,
};

enum class Addressing : std::uint8_t { None, AutoIncrement, Configured, Broadcast, Logical, Unknown };

Addressing addressing_of(Command command);
bool is_known(Command command);
// Whether the command reads slave memory into the datagram / writes the datagram into slave memory.
// ARMW/FRMW count as both (the addressed slave reads, the others write).
bool command_reads(Command command);
bool command_writes(Command command);

// "LRW", or "CMD(0x1f)" for a reserved code.
std::string to_string(Command command);
// "LRW" / "lrw" -> Command::Lrw.
bool parse_command(std::string_view name, Command& out);

}  // namespace ecpair::wire
