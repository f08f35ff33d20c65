#pragma once
// Parsers for the text of one ENI value: numbers, booleans, hexBinary and the
// enumerations (transition codes, states, SyncManager types...). Each returns
// the value or a message naming the problem ("'70000' is out of range
// 0..65535"); the element reader adds where it happened. They accept what
// real exporters write, not only what the schema says (docs/ENI.md).

#include <concepts>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include "ecpair/common/expected.hpp"
#include "ecpair/eni/model.hpp"
#include "ecpair/wire/command.hpp"

namespace ecpair::eni::detail {

template <class T>
using ValueResult = Expected<T, std::string>;

// The text without surrounding whitespace.
std::string_view trim(std::string_view text);

// The text as it goes into a message: quoted, and shortened when long.
std::string in_quotes(std::string_view text);

// "1001", "#x03E9", "0x03E9", "-1", "+7" (surrounding whitespace ignored).
// Values beyond the int64 range saturate, so they fail any field's range check.
std::optional<std::int64_t> parse_integer(std::string_view text);

// How a field of an unsigned type treats a negative number.
enum class Negative {
    Reject,
    // -1 means 0xFFFF for a 16-bit field: the schema types AutoIncAddr and Adp
    // as signed; some exporters write IDs as signed 32-bit numbers.
    TwosComplement,
};

// A number for a field of type T, range-checked against T.
template <std::integral T>
ValueResult<T> parse_number(std::string_view text, Negative negative = Negative::Reject) {
    const auto value = parse_integer(text);
    if (!value) return unexpected(in_quotes(text) + " is not a number (expected decimal or #x hex)");
    constexpr std::int64_t kMax = static_cast<std::int64_t>(std::numeric_limits<T>::max());
    std::int64_t min = static_cast<std::int64_t>(std::numeric_limits<T>::min());
    if constexpr (std::is_unsigned_v<T>) {
        if (negative == Negative::TwosComplement) min = -(kMax / 2) - 1;
    }
    if (*value < min || *value > kMax) {
        return unexpected(in_quotes(text) + " is out of range " + std::to_string(min) + ".." + std::to_string(kMax));
    }
    return static_cast<T>(*value);  // a negative value wraps to its two's complement
}

// 1, 0, true, false in any letter case.
ValueResult<bool> parse_boolean(std::string_view text);

// Hex digit pairs in wire order ("e903"); whitespace between digits is ignored.
ValueResult<std::vector<std::uint8_t>> parse_hex_binary(std::string_view text);

ValueResult<Transition> parse_transition(std::string_view text);

// A cyclic command state: INIT, PREOP, BOOT, SAFEOP, OP.
ValueResult<SlaveState> parse_state(std::string_view text);

// Outputs, Inputs, MBoxOut/MailboxOut, MBoxIn/MailboxIn, Unused.
ValueResult<SmType> parse_sm_type(std::string_view text);

// AoE, EoE, CoE, FoE, SoE, VoE; nullopt for anything else.
std::optional<MailboxProtocol> parse_protocol(std::string_view text);

ValueResult<Requires> parse_requires(std::string_view text);

// The datagram type number (1 APRD ... 14 FRMW) or its name ("LRW").
ValueResult<wire::Command> parse_command_code(std::string_view text);

}  // namespace ecpair::eni::detail
