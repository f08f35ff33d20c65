// Parsing of ecsim control requests. The line is split into words; the
// first names the command, which fixes how many numeric arguments follow.
// Every rejection says what was wrong and what the command expects, so a
// person at `ecsim ctl` can correct it without the docs.

#include "ecpair/sim/control_protocol.hpp"

#include <fmt/format.h>

#include <array>
#include <charconv>
#include <optional>

namespace ecpair::sim {

namespace {

struct CommandSyntax {
    ControlCommand command;
    std::string_view word;
    std::string_view arguments;  // as shown in the usage text
    int argument_count;
};

constexpr std::array<CommandSyntax, 11> kSyntax{{
    {ControlCommand::Status, "status", "", 0},
    {ControlCommand::Help, "help", "", 0},
    {ControlCommand::PowerOff, "power-off", "K", 1},
    {ControlCommand::PowerOn, "power-on", "K", 1},
    {ControlCommand::Break, "break", "K", 1},
    {ControlCommand::Repair, "repair", "K", 1},
    {ControlCommand::InsertUnknown, "insert-unknown", "K", 1},
    {ControlCommand::RemoveUnknown, "remove-unknown", "K", 1},
    {ControlCommand::SetAlias, "set-alias", "K VALUE", 2},
    {ControlCommand::SetId, "set-id", "K VALUE", 2},
    {ControlCommand::Impair, "impair", "main|red LOSS% DUP% DELAY_US", 4},
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
    if (given != syntax->argument_count) {
        return unexpected(
            ControlParseError{fmt::format("{} takes {} argument{}, got {}: {}", syntax->word, syntax->argument_count,
                                          syntax->argument_count == 1 ? "" : "s", given, usage_of(*syntax))});
    }

    ControlRequest request;
    request.command = syntax->command;
    if (syntax->command == ControlCommand::Impair) return parse_impairment(request, words);
    if (syntax->argument_count >= 1) {
        const auto position = parse_number(words[1], false, 0xFFFF);
        if (!position) {
            return unexpected(ControlParseError{fmt::format("{}: K must be a decimal number in 0..65535, got '{}'",
                                                            syntax->word, printable(words[1]))});
        }
        request.position = *position;
    }
    if (syntax->argument_count == 2) {
        const auto value = parse_number(words[2], true, 0xFFFF);
        if (!value) {
            return unexpected(
                ControlParseError{fmt::format("{}: VALUE must be a number in 0..65535 (decimal or 0x hex), got '{}'",
                                              syntax->word, printable(words[2]))});
        }
        request.value = static_cast<std::uint16_t>(*value);
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
