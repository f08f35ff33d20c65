// Value parsers. Everything is trimmed first and compared without regard to
// letter case where real files disagree on case (booleans, enumerations); the
// messages quote the offending text so a user can find it in the file.

#include "values.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <utility>

#include <fmt/format.h>

#include "ecpair/common/hex.hpp"

namespace ecpair::eni::detail {
namespace {

constexpr std::size_t kMaxQuotedLength = 40;

bool equals_ignoring_case(std::string_view a, std::string_view b) {
    return a.size() == b.size() && std::equal(a.begin(), a.end(), b.begin(), [](char x, char y) {
               return std::tolower(static_cast<unsigned char>(x)) == std::tolower(static_cast<unsigned char>(y));
           });
}

int digit_value(char c, unsigned base) {
    int value = -1;
    if (c >= '0' && c <= '9') value = c - '0';
    if (c >= 'a' && c <= 'f') value = c - 'a' + 10;
    if (c >= 'A' && c <= 'F') value = c - 'A' + 10;
    return value >= 0 && static_cast<unsigned>(value) < base ? value : -1;
}

// Looks `text` up in a table of (name, value) pairs, ignoring case.
template <class T, std::size_t N>
std::optional<T> lookup(std::string_view text, const std::array<std::pair<std::string_view, T>, N>& table) {
    for (const auto& [name, value] : table) {
        if (equals_ignoring_case(text, name)) return value;
    }
    return std::nullopt;
}

}  // namespace

std::string_view trim(std::string_view text) {
    const auto is_space = [](char c) { return std::isspace(static_cast<unsigned char>(c)) != 0; };
    while (!text.empty() && is_space(text.front())) text.remove_prefix(1);
    while (!text.empty() && is_space(text.back())) text.remove_suffix(1);
    return text;
}

// Formatted rather than concatenated: GCC 12 at -O3 reports a false
// -Wrestrict in the inlined operator+(const char*, std::string&&).
std::string in_quotes(std::string_view text) {
    if (text.size() <= kMaxQuotedLength) return fmt::format("'{}'", text);
    return fmt::format("'{}...'", text.substr(0, kMaxQuotedLength));
}

std::optional<std::int64_t> parse_integer(std::string_view text) {
    text = trim(text);
    bool negative = false;
    if (!text.empty() && (text.front() == '-' || text.front() == '+')) {
        negative = text.front() == '-';
        text.remove_prefix(1);
    }
    unsigned base = 10;
    if (text.starts_with("#x") || text.starts_with("#X") || text.starts_with("0x") || text.starts_with("0X")) {
        base = 16;
        text.remove_prefix(2);
    }
    if (text.empty()) return std::nullopt;

    constexpr std::uint64_t kLimit = static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max());
    std::uint64_t magnitude = 0;
    for (const char c : text) {
        const int digit = digit_value(c, base);
        if (digit < 0) return std::nullopt;
        if (magnitude <= kLimit) magnitude = magnitude * base + static_cast<unsigned>(digit);
    }
    if (magnitude > kLimit) magnitude = kLimit;  // saturate: no field is that wide
    const auto value = static_cast<std::int64_t>(magnitude);
    return negative ? -value : value;
}

ValueResult<bool> parse_boolean(std::string_view text) {
    const auto value = trim(text);
    if (value == "1" || equals_ignoring_case(value, "true")) return true;
    if (value == "0" || equals_ignoring_case(value, "false")) return false;
    return unexpected(in_quotes(text) + " is not a boolean (expected 1, 0, true or false)");
}

ValueResult<std::vector<std::uint8_t>> parse_hex_binary(std::string_view text) {
    auto bytes = parse_hex(text);
    if (bytes) return std::move(*bytes);
    const auto digits = std::count_if(text.begin(), text.end(),
                                      [](char c) { return std::isxdigit(static_cast<unsigned char>(c)) != 0; });
    const auto spaces = std::count_if(text.begin(), text.end(),
                                      [](char c) { return std::isspace(static_cast<unsigned char>(c)) != 0; });
    if (static_cast<std::size_t>(digits + spaces) != text.size()) {
        return unexpected(in_quotes(text) + " is not hexBinary (only hex digits are allowed)");
    }
    return unexpected(in_quotes(text) + " is not hexBinary (odd number of hex digits)");
}

ValueResult<Transition> parse_transition(std::string_view text) {
    static constexpr std::array<std::pair<std::string_view, Transition>, kTransitionCount> kCodes{{
        {"IP", Transition::IP}, {"PS", Transition::PS}, {"SO", Transition::SO}, {"SP", Transition::SP},
        {"OP", Transition::OP}, {"OS", Transition::OS}, {"PI", Transition::PI}, {"SI", Transition::SI},
        {"OI", Transition::OI}, {"IB", Transition::IB}, {"BI", Transition::BI}, {"II", Transition::II},
        {"PP", Transition::PP},
    }};
    if (auto code = lookup(trim(text), kCodes)) return *code;
    return unexpected("unknown transition code " + in_quotes(text) +
                      " (expected IP, PS, SO, SP, OP, OS, PI, SI, OI, IB, BI, II or PP)");
}

ValueResult<SlaveState> parse_state(std::string_view text) {
    static constexpr std::array<std::pair<std::string_view, SlaveState>, 5> kStates{{
        {"INIT", SlaveState::Init},
        {"PREOP", SlaveState::Preop},
        {"BOOT", SlaveState::Boot},
        {"SAFEOP", SlaveState::Safeop},
        {"OP", SlaveState::Op},
    }};
    if (auto state = lookup(trim(text), kStates)) return *state;
    return unexpected("unknown state " + in_quotes(text) + " (expected INIT, PREOP, BOOT, SAFEOP or OP)");
}

ValueResult<SmType> parse_sm_type(std::string_view text) {
    static constexpr std::array<std::pair<std::string_view, SmType>, 7> kTypes{{
        {"Outputs", SmType::Outputs},
        {"Inputs", SmType::Inputs},
        {"MBoxOut", SmType::MailboxOut},
        {"MailboxOut", SmType::MailboxOut},
        {"MBoxIn", SmType::MailboxIn},
        {"MailboxIn", SmType::MailboxIn},
        {"Unused", SmType::Unused},
    }};
    if (auto type = lookup(trim(text), kTypes)) return *type;
    return unexpected("unknown SyncManager type " + in_quotes(text) + " (expected Outputs, Inputs, MBoxOut, MBoxIn or Unused)");
}

std::optional<MailboxProtocol> parse_protocol(std::string_view text) {
    static constexpr std::array<std::pair<std::string_view, MailboxProtocol>, 6> kProtocols{{
        {"AoE", kAoE}, {"EoE", kEoE}, {"CoE", kCoE}, {"FoE", kFoE}, {"SoE", kSoE}, {"VoE", kVoE},
    }};
    return lookup(trim(text), kProtocols);
}

ValueResult<Requires> parse_requires(std::string_view text) {
    static constexpr std::array<std::pair<std::string_view, Requires>, 2> kValues{{
        {"cycle", Requires::Cycle},
        {"frame", Requires::Frame},
    }};
    if (auto value = lookup(trim(text), kValues)) return *value;
    return unexpected("unknown Requires value " + in_quotes(text) + " (expected cycle or frame)");
}

ValueResult<wire::Command> parse_command_code(std::string_view text) {
    wire::Command by_name{};
    if (wire::parse_command(trim(text), by_name)) return by_name;
    const auto code = parse_number<std::uint8_t>(text);
    if (!code) return unexpected(code.error());
    const auto command = static_cast<wire::Command>(*code);
    if (!wire::is_known(command)) {
        return unexpected("command code " + in_quotes(text) + " is not an EtherCAT datagram type (0..14)");
    }
    return command;
}

}  // namespace ecpair::eni::detail
