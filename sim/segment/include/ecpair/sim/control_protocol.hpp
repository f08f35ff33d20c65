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
//   impair SIDE LOSS DUP DELAY
//
// K is a decimal number; VALUE is decimal or 0x-prefixed hexadecimal, 0..65535.
// impair: the cable on SIDE (main or red) loses LOSS % and duplicates DUP %
// of the frames crossing it (either way), and delays those entering the
// segment by DELAY µs (0..100000): netem's job, for kernels without netem.
// impair SIDE 0 0 0 ends it.
// Words are separated by spaces or tabs; a trailing CR is ignored.

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
    Impair,
};

std::string_view to_string(ControlCommand command);  // the request word, "power-off"

struct ControlRequest {
    ControlCommand command = ControlCommand::Status;
    std::size_t position = 0;  // K, for the commands that take one
    std::uint16_t value = 0;   // VALUE, for set-alias / set-id
    // impair
    bool red_side = false;
    std::uint8_t loss_percent = 0;
    std::uint8_t duplicate_percent = 0;
    std::uint32_t delay_us = 0;

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
