#pragma once
// ecsim's control protocol: one request line in, one response line out
// (docs/ECSIM.md). This header is the request grammar, as a pure parser
// (fuzzed by fuzz_ecsim_control), and the response helpers; what a request
// does to a segment is in control_commands.hpp.
//
//   status | help
//   power-off K | power-on K | break K | repair K
//   insert-unknown K | remove-unknown K
//   set-alias K VALUE | set-id K VALUE
//   group-off N | group-on N | plug-group N K PORT | unplug-group N
//   plug-unknown K PORT | plug-duplicate K J PORT
//   refuse-state K STATE | set-selector K VALUE
//   emergency K CODE [REG [DATA]] | foe-password K PASSWORD | foe-busy K N
//   port-errors K PORT N
//   impair SIDE LOSS DUP DELAY
//   dc | dc --json | dc reset
//
// K, J and N are decimal numbers (slave positions, a Hot-Connect group);
// VALUE is decimal or 0x-prefixed hexadecimal, 0..65535; PORT is A..D (or
// 0..3); STATE is PREOP, SAFEOP, OP or none; N (port-errors) a frame count,
// 1..1000000.
// emergency: slave K sends a CoE emergency with error code CODE (0..65535),
// error register REG (0..255, default 0) and DATA (up to 5 bytes as hex
// digits, e.g. 0102030405; default zeros). foe-password: slave K's FoE
// server asks for PASSWORD (0..4294967295, decimal or 0x hex; 0: none).
// foe-busy: it answers the next N data packets of a write BUSY.
// port-errors: the next N frames arriving at port PORT of slave K are
// damaged there (its invalid frame and RX error counters count them, the
// ports after it count forwarded errors; the master loses them).
// impair: the cable on SIDE (main or red) damages LOSS % and duplicates DUP %
// of the frames crossing it (either way), and delays those entering the
// segment by DELAY µs (0..100000): netem's job, for kernels without netem.
// A damaged frame never reaches the master; one damaged on its way in is
// counted by the error counters of the slave port it reaches.
// impair SIDE 0 0 0 ends it.
// dc: the distributed clocks' truth (as text, or as JSON); dc reset starts
// the worst deviation and the missed SYNC0 edges anew.
// Words are separated by spaces or tabs; a trailing CR is ignored.

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include "ecpair/common/expected.hpp"

namespace ecpair::sim {

enum class ControlCommand : std::uint8_t {
    Status,
    Help,
    PowerOff,
    PowerOn,
    Break,
    Repair,
    InsertUnknown,
    RemoveUnknown,
    SetAlias,
    SetId,
    GroupOff,
    GroupOn,
    PlugGroup,
    UnplugGroup,
    PlugUnknown,
    PlugDuplicate,
    RefuseState,
    SetSelector,
    PortErrors,
    Impair,
    Emergency,
    FoePassword,
    FoeBusy,
    Dc,
};

// What `dc` does.
enum class DcRequest : std::uint8_t { Text, Json, Reset };

std::string_view to_string(ControlCommand command);  // the request word, "power-off"

struct ControlRequest {
    ControlCommand command = ControlCommand::Status;
    std::size_t position = 0;  // K, for the commands that take one
    std::uint16_t value = 0;   // VALUE, for set-alias / set-id / set-selector
    std::size_t group = 0;     // N
    std::size_t at = 0;        // J (plug-duplicate), K (plug-group)
    int port = 0;              // PORT, 0..3
    std::uint8_t state = 0;    // STATE as an AL state (2, 4, 8), 0 for none
    // emergency (CODE in value)
    std::uint8_t error_register = 0;
    std::array<std::uint8_t, 5> emergency_data{};
    std::uint32_t password = 0;  // foe-password
    std::uint32_t count = 0;   // N (port-errors)
    // impair
    bool red_side = false;
    std::uint8_t loss_percent = 0;
    std::uint8_t duplicate_percent = 0;
    std::uint32_t delay_us = 0;
    DcRequest dc = DcRequest::Text;

    friend bool operator==(const ControlRequest&, const ControlRequest&) = default;
};

struct ControlParseError {
    std::string message;  // "power-off needs a slave position: power-off K"
};

// The longest request line a server accepts (a longer one is refused).
inline constexpr std::size_t kMaxControlLineLength = 256;

Expected<ControlRequest, ControlParseError> parse_control_request(std::string_view line);

// The help text, as one line: every request with its arguments.
std::string control_usage();

// Response lines (without the newline).
std::string control_ok(std::string_view detail = {});  // "ok" or "ok <detail>"
std::string control_error(std::string_view message);   // "error: <message>"

}  // namespace ecpair::sim
