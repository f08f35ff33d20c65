// Parsing of ecsim control requests. The line is split into words; the
// first names the command, which fixes how many numeric arguments follow.
// Every rejection says what was wrong and what the command expects, so a
// person at `ecsim ctl` can correct it without the docs.

#include "ecpair/sim/control_protocol.hpp"

#include "ecpair/common/hex.hpp"
#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <charconv>
#include <optional>

namespace ecpair::sim {

namespace {

// What each argument word is.
enum class Arg : std::uint8_t { Position, Value, Group, At, Port, State, Count };

constexpr std::uint32_t kMaxFrameCount = 1'000'000;

struct CommandSyntax {
    ControlCommand command;
    std::string_view word;
    std::string_view arguments;  // as shown in the usage text
    int argument_count;
    std::array<Arg, 3> kinds;
};

constexpr std::array<CommandSyntax, 24> kSyntax{{
    {ControlCommand::Status, "status", "", 0, {}},
    {ControlCommand::Help, "help", "", 0, {}},
    {ControlCommand::PowerOff, "power-off", "K", 1, {Arg::Position}},
    {ControlCommand::PowerOn, "power-on", "K", 1, {Arg::Position}},
    {ControlCommand::Break, "break", "K", 1, {Arg::Position}},
    {ControlCommand::Repair, "repair", "K", 1, {Arg::Position}},
    {ControlCommand::InsertUnknown, "insert-unknown", "K", 1, {Arg::Position}},
    {ControlCommand::RemoveUnknown, "remove-unknown", "K", 1, {Arg::Position}},
    {ControlCommand::SetAlias, "set-alias", "K VALUE", 2, {Arg::Position, Arg::Value}},
    {ControlCommand::SetId, "set-id", "K VALUE", 2, {Arg::Position, Arg::Value}},
    {ControlCommand::GroupOff, "group-off", "N", 1, {Arg::Group}},
    {ControlCommand::GroupOn, "group-on", "N", 1, {Arg::Group}},
    {ControlCommand::PlugGroup, "plug-group", "N K PORT", 3, {Arg::Group, Arg::At, Arg::Port}},
    {ControlCommand::UnplugGroup, "unplug-group", "N", 1, {Arg::Group}},
    {ControlCommand::PlugUnknown, "plug-unknown", "K PORT", 2, {Arg::Position, Arg::Port}},
    {ControlCommand::PlugDuplicate, "plug-duplicate", "K J PORT", 3, {Arg::Position, Arg::At, Arg::Port}},
    {ControlCommand::RefuseState, "refuse-state", "K STATE", 2, {Arg::Position, Arg::State}},
    {ControlCommand::SetSelector, "set-selector", "K VALUE", 2, {Arg::Position, Arg::Value}},
    {ControlCommand::PortErrors, "port-errors", "K PORT N", 3, {Arg::Position, Arg::Port, Arg::Count}},
    {ControlCommand::Impair, "impair", "main|red LOSS% DUP% DELAY_US", 4, {}},  // parsed by parse_impairment
    {ControlCommand::Emergency, "emergency", "K CODE [REG [DATA]]", 2, {}},      // parsed by parse_emergency
    {ControlCommand::FoePassword, "foe-password", "K PASSWORD", 2, {}},          // parsed by parse_foe_password
    {ControlCommand::FoeBusy, "foe-busy", "K N", 2, {Arg::Position, Arg::Value}},
    {ControlCommand::Dc, "dc", "[--json|reset]", -1, {}},                       // parsed by parse_dc
}};

constexpr std::size_t kMaxWords = 5;

bool is_blank(char c) { return c == ' ' || c == '\t'; }

std::string printable(std::string_view text) {
    std::string out;
    for (const char c : text.substr(0, 40)) {
        const auto byte = static_cast<unsigned char>(c);
        out += (byte >= 0x20 && byte < 0x7F) ? std::string(1, c) : fmt::format("\\x{:02x}", byte);
    }
    if (text.size() > 40) out += "...";
    return out;
}

// A number in 0..max: decimal, or hexadecimal with 0x when hex_allowed.
std::optional<std::uint32_t> parse_number(std::string_view word, bool hex_allowed, std::uint32_t max) {
    int base = 10;
    if (hex_allowed && word.size() > 2 && word[0] == '0' && (word[1] == 'x' || word[1] == 'X')) {
        word.remove_prefix(2);
        base = 16;
    }
    if (word.empty()) return std::nullopt;
    std::uint32_t value = 0;
    const auto [end, error] = std::from_chars(word.data(), word.data() + word.size(), value, base);
    if (error != std::errc() || end != word.data() + word.size() || value > max) return std::nullopt;
    return value;
}

// A port letter A..D or number 0..3.
std::optional<int> parse_port(std::string_view word) {
    if (word.size() != 1) return std::nullopt;
    if (word[0] >= 'A' && word[0] <= 'D') return word[0] - 'A';
    if (word[0] >= '0' && word[0] <= '3') return word[0] - '0';
    return std::nullopt;
}

// PREOP, SAFEOP, OP as AL state values, none as 0.
std::optional<std::uint8_t> parse_state(std::string_view word) {
    if (word == "PREOP") return std::uint8_t{2};
    if (word == "SAFEOP") return std::uint8_t{4};
    if (word == "OP") return std::uint8_t{8};
    if (word == "none") return std::uint8_t{0};
    return std::nullopt;
}

// A response must stay on one line: control characters (slave names from
// an ENI may hold a newline) become spaces.
std::string single_line(std::string_view text) {
    std::string out(text);
    for (char& c : out) {
        if (static_cast<unsigned char>(c) < 0x20 || c == 0x7F) c = ' ';
    }
    return out;
}

// impair SIDE LOSS DUP DELAY (the word count is checked already).
Expected<ControlRequest, ControlParseError> parse_impairment(ControlRequest request,
                                                            const std::array<std::string_view, kMaxWords>& words) {
    if (words[1] != "main" && words[1] != "red") {
        return unexpected(ControlParseError{fmt::format("impair: SIDE must be main or red, got '{}'", printable(words[1]))});
    }
    request.red_side = words[1] == "red";
    const auto loss = parse_number(words[2], false, 100);
    const auto duplicate = parse_number(words[3], false, 100);
    const auto delay = parse_number(words[4], false, 100'000);
    if (!loss || !duplicate) {
        return unexpected(ControlParseError{fmt::format("impair: LOSS% and DUP% must be 0..100, got '{}' '{}'",
                                                        printable(words[2]), printable(words[3]))});
    }
    if (!delay) {
        return unexpected(
            ControlParseError{fmt::format("impair: DELAY_US must be 0..100000, got '{}'", printable(words[4]))});
    }
    request.loss_percent = static_cast<std::uint8_t>(*loss);
    request.duplicate_percent = static_cast<std::uint8_t>(*duplicate);
    request.delay_us = *delay;
    return request;
}

// emergency K CODE [REG [DATA]]: 2 to 4 arguments (the count is checked already).
Expected<ControlRequest, ControlParseError> parse_emergency(ControlRequest request,
                                                           const std::array<std::string_view, kMaxWords>& words,
                                                           std::size_t count) {
    const auto position = parse_number(words[1], false, 0xFFFF);
    if (!position) {
        return unexpected(ControlParseError{
            fmt::format("emergency: K must be a decimal number in 0..65535, got '{}'", printable(words[1]))});
    }
    request.position = *position;
    const auto code = parse_number(words[2], true, 0xFFFF);
    if (!code) {
        return unexpected(ControlParseError{fmt::format(
            "emergency: CODE must be a number in 0..65535 (decimal or 0x hex), got '{}'", printable(words[2]))});
    }
    request.value = static_cast<std::uint16_t>(*code);
    if (count > 3) {
        const auto reg = parse_number(words[3], true, 0xFF);
        if (!reg) {
            return unexpected(ControlParseError{fmt::format(
                "emergency: REG must be a number in 0..255 (decimal or 0x hex), got '{}'", printable(words[3]))});
        }
        request.error_register = static_cast<std::uint8_t>(*reg);
    }
    if (count > 4) {
        std::string_view digits = words[4];
        if (digits.size() > 2 && digits[0] == '0' && (digits[1] == 'x' || digits[1] == 'X')) digits.remove_prefix(2);
        const auto data = parse_hex(digits);
        if (!data || data->empty() || data->size() > request.emergency_data.size() ||
            digits.find_first_of(" \t") != std::string_view::npos) {
            return unexpected(ControlParseError{fmt::format(
                "emergency: DATA must be 1 to 5 bytes as hex digits (0102030405), got '{}'", printable(words[4]))});
        }
        std::copy(data->begin(), data->end(), request.emergency_data.begin());
    }
    return request;
}

// dc [--json|reset] (the word count is checked already).
Expected<ControlRequest, ControlParseError> parse_dc(ControlRequest request, std::size_t count,
                                                     const std::array<std::string_view, kMaxWords>& words) {
    if (count == 1) return request;
    if (words[1] == "--json") {
        request.dc = DcRequest::Json;
    } else if (words[1] == "reset") {
        request.dc = DcRequest::Reset;
    } else {
        return unexpected(ControlParseError{fmt::format("dc: expected --json or reset, got '{}'", printable(words[1]))});
    }
    return request;
}

Expected<ControlRequest, ControlParseError> parse_foe_password(ControlRequest request,
                                                              const std::array<std::string_view, kMaxWords>& words) {
    const auto position = parse_number(words[1], false, 0xFFFF);
    if (!position) {
        return unexpected(ControlParseError{
            fmt::format("foe-password: K must be a decimal number in 0..65535, got '{}'", printable(words[1]))});
    }
    request.position = *position;
    const auto password = parse_number(words[2], true, 0xFFFFFFFF);
    if (!password) {
        return unexpected(ControlParseError{fmt::format(
            "foe-password: PASSWORD must be a number in 0..4294967295 (decimal or 0x hex), got '{}'",
            printable(words[2]))});
    }
    request.password = *password;
    return request;
}

std::string usage_of(const CommandSyntax& syntax) {
    return syntax.arguments.empty() ? std::string(syntax.word) : fmt::format("{} {}", syntax.word, syntax.arguments);
}

}  // namespace

std::string_view to_string(ControlCommand command) {
    for (const auto& syntax : kSyntax) {
        if (syntax.command == command) return syntax.word;
    }
    return "?";
}

Expected<ControlRequest, ControlParseError> parse_control_request(std::string_view line) {
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    if (line.size() > kMaxControlLineLength) {
        return unexpected(ControlParseError{
            fmt::format("request is {} characters long; the limit is {}", line.size(), kMaxControlLineLength)});
    }

    std::array<std::string_view, kMaxWords> words{};
    std::size_t count = 0;
    std::size_t i = 0;
    while (i < line.size()) {
        while (i < line.size() && is_blank(line[i])) ++i;
        if (i == line.size()) break;
        const std::size_t start = i;
        while (i < line.size() && !is_blank(line[i])) ++i;
        if (count == kMaxWords) {
            return unexpected(ControlParseError{fmt::format("too many words in '{}'", printable(line))});
        }
        words[count++] = line.substr(start, i - start);
    }
    if (count == 0) return unexpected(ControlParseError{"empty request (try 'help')"});

    const CommandSyntax* syntax = nullptr;
    for (const auto& candidate : kSyntax) {
        if (candidate.word == words[0]) syntax = &candidate;
    }
    if (syntax == nullptr) {
        return unexpected(ControlParseError{fmt::format("unknown command '{}' (try 'help')", printable(words[0]))});
    }
    const auto given = static_cast<int>(count) - 1;
    if (syntax->command == ControlCommand::Emergency) {
        if (given < 2 || given > 4) {
            return unexpected(ControlParseError{
                fmt::format("emergency takes 2 to 4 arguments, got {}: {}", given, usage_of(*syntax))});
        }
        ControlRequest request;
        request.command = syntax->command;
        return parse_emergency(request, words, count);
    }
    if (syntax->command == ControlCommand::Dc) {
        if (given > 1) {
            return unexpected(ControlParseError{fmt::format("dc takes at most 1 argument, got {}: {}", given, usage_of(*syntax))});
        }
        ControlRequest request;
        request.command = ControlCommand::Dc;
        return parse_dc(request, count, words);
    }
    if (given != syntax->argument_count) {
        return unexpected(
            ControlParseError{fmt::format("{} takes {} argument{}, got {}: {}", syntax->word, syntax->argument_count,
                                          syntax->argument_count == 1 ? "" : "s", given, usage_of(*syntax))});
    }

    ControlRequest request;
    request.command = syntax->command;
    if (syntax->command == ControlCommand::Impair) return parse_impairment(request, words);
    if (syntax->command == ControlCommand::FoePassword) return parse_foe_password(request, words);
    for (int n = 0; n < syntax->argument_count; ++n) {
        const std::string_view word = words[static_cast<std::size_t>(n) + 1];
        const Arg kind = syntax->kinds[static_cast<std::size_t>(n)];
        switch (kind) {
            case Arg::Position:
            case Arg::Group:
            case Arg::At: {
                const auto number = parse_number(word, false, 0xFFFF);
                // The argument's name in the usage text: N, K, or J (K for plug-group's slave).
                const bool plug_group = syntax->command == ControlCommand::PlugGroup;
                const std::string_view label = kind == Arg::Group ? "N" : kind == Arg::At && !plug_group ? "J" : "K";
                if (!number) {
                    return unexpected(ControlParseError{fmt::format("{}: {} must be a decimal number in 0..65535, got '{}'",
                                                                    syntax->word, label, printable(word))});
                }
                (kind == Arg::Position ? request.position : kind == Arg::Group ? request.group : request.at) = *number;
                break;
            }
            case Arg::Value: {
                const auto value = parse_number(word, true, 0xFFFF);
                if (!value) {
                    return unexpected(ControlParseError{
                        fmt::format("{}: VALUE must be a number in 0..65535 (decimal or 0x hex), got '{}'", syntax->word,
                                    printable(word))});
                }
                request.value = static_cast<std::uint16_t>(*value);
                break;
            }
            case Arg::Port: {
                const auto port = parse_port(word);
                if (!port) {
                    return unexpected(ControlParseError{
                        fmt::format("{}: PORT must be A, B, C or D (or 0..3), got '{}'", syntax->word, printable(word))});
                }
                request.port = *port;
                break;
            }
            case Arg::Count: {
                const auto frames = parse_number(word, false, kMaxFrameCount);
                if (!frames || *frames == 0) {
                    return unexpected(ControlParseError{fmt::format("{}: N must be a decimal number in 1..{}, got '{}'",
                                                                    syntax->word, kMaxFrameCount, printable(word))});
                }
                request.count = *frames;
                break;
            }
            case Arg::State: {
                const auto state = parse_state(word);
                if (!state) {
                    return unexpected(ControlParseError{fmt::format(
                        "{}: STATE must be PREOP, SAFEOP, OP or none, got '{}'", syntax->word, printable(word))});
                }
                request.state = *state;
                break;
            }
        }
    }
    return request;
}

std::string control_usage() {
    std::string text = "commands:";
    for (const auto& syntax : kSyntax) {
        text += ' ';
        text += usage_of(syntax);
        text += ';';
    }
    text.pop_back();
    return text;
}

std::string control_ok(std::string_view detail) {
    return detail.empty() ? std::string("ok") : fmt::format("ok {}", single_line(detail));
}

std::string control_error(std::string_view message) { return fmt::format("error: {}", single_line(message)); }

}  // namespace ecpair::sim
