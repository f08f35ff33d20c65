// Encoding handling (docs/ENI.md "Text encoding"):
//   - declared ISO-8859-1 (or latin1, or windows-1252, read as ISO-8859-1):
//     every byte >= 0x80 becomes its two-byte UTF-8 sequence;
//   - declared UTF-8 / US-ASCII, or nothing declared: kept when valid UTF-8;
//     when not, it is almost certainly a legacy 8-bit export, so it is read as
//     ISO-8859-1 and the caller logs a warning;
//   - any other declared encoding is refused with a message.

#include "text_encoding.hpp"

#include <algorithm>
#include <array>
#include <cctype>

#include "values.hpp"

namespace ecpair::eni::detail {
namespace {

std::string lower(std::string_view text) {
    std::string out(text);
    std::transform(out.begin(), out.end(), out.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return out;
}

bool is_latin1_name(const std::string& name) {
    static constexpr std::array<std::string_view, 7> kNames = {
        "iso-8859-1", "iso8859-1", "iso_8859-1", "latin1", "latin-1", "windows-1252", "cp1252"};
    return std::find(kNames.begin(), kNames.end(), name) != kNames.end();
}

bool is_utf8_name(const std::string& name) {
    return name == "utf-8" || name == "utf8" || name == "us-ascii" || name == "ascii";
}

// The length of the valid UTF-8 sequence starting at `at`, or 0 when the
// bytes there are not one (overlong forms and surrogates included).
std::size_t utf8_sequence_length(std::string_view text, std::size_t at) {
    const auto byte = [&](std::size_t i) { return static_cast<unsigned char>(text[i]); };
    const unsigned char lead = byte(at);
    if (lead < 0x80) return 1;
    std::size_t length = 0;
    unsigned char min_second = 0x80;
    unsigned char max_second = 0xBF;
    if (lead >= 0xC2 && lead <= 0xDF) {
        length = 2;
    } else if (lead >= 0xE0 && lead <= 0xEF) {
        length = 3;
        if (lead == 0xE0) min_second = 0xA0;
        if (lead == 0xED) max_second = 0x9F;
    } else if (lead >= 0xF0 && lead <= 0xF4) {
        length = 4;
        if (lead == 0xF0) min_second = 0x90;
        if (lead == 0xF4) max_second = 0x8F;
    } else {
        return 0;
    }
    if (at + length > text.size()) return 0;
    if (byte(at + 1) < min_second || byte(at + 1) > max_second) return 0;
    for (std::size_t i = 2; i < length; ++i) {
        if (byte(at + i) < 0x80 || byte(at + i) > 0xBF) return 0;
    }
    return length;
}

// The offset of the first byte that does not start a valid UTF-8 sequence.
std::optional<std::size_t> first_invalid_utf8(std::string_view text) {
    std::size_t at = 0;
    while (at < text.size()) {
        const std::size_t length = utf8_sequence_length(text, at);
        if (length == 0) return at;
        at += length;
    }
    return std::nullopt;
}

std::string latin1_to_utf8(std::string_view text) {
    std::string out;
    out.reserve(text.size() + text.size() / 8);
    for (const char c : text) {
        const auto byte = static_cast<unsigned char>(c);
        if (byte < 0x80) {
            out.push_back(c);
        } else {
            out.push_back(static_cast<char>(0xC0 | (byte >> 6)));
            out.push_back(static_cast<char>(0x80 | (byte & 0x3F)));
        }
    }
    return out;
}

}  // namespace

std::optional<std::string> declared_encoding(std::string_view document) {
    if (document.starts_with("\xEF\xBB\xBF")) document.remove_prefix(3);
    if (!document.starts_with("<?xml")) return std::nullopt;
    const auto end = document.find("?>");
    if (end == std::string_view::npos) return std::nullopt;
    const std::string_view declaration = document.substr(0, end);
    const auto key = declaration.find("encoding");
    if (key == std::string_view::npos) return std::nullopt;
    std::size_t at = key + std::string_view("encoding").size();
    const auto skip_spaces = [&] {
        while (at < declaration.size() && std::isspace(static_cast<unsigned char>(declaration[at]))) ++at;
    };
    skip_spaces();
    if (at >= declaration.size() || declaration[at] != '=') return std::nullopt;
    ++at;
    skip_spaces();
    if (at >= declaration.size() || (declaration[at] != '"' && declaration[at] != '\'')) return std::nullopt;
    const char quote = declaration[at++];
    const auto close = declaration.find(quote, at);
    if (close == std::string_view::npos) return std::nullopt;
    return std::string(declaration.substr(at, close - at));
}

Expected<Utf8Text, std::string> to_utf8(std::string_view document) {
    const auto declared = declared_encoding(document);
    const std::string name = declared ? lower(*declared) : std::string();
    if (is_latin1_name(name)) return Utf8Text{latin1_to_utf8(document), std::nullopt};
    if (!name.empty() && !is_utf8_name(name)) {
        return unexpected("the declared encoding " + in_quotes(*declared) + " is not supported (UTF-8 and ISO-8859-1 are)");
    }
    const auto invalid = first_invalid_utf8(document);
    if (!invalid) return Utf8Text{std::string(document), std::nullopt};
    const auto line = 1 + std::count(document.begin(), document.begin() + static_cast<std::ptrdiff_t>(*invalid), '\n');
    return Utf8Text{latin1_to_utf8(document), static_cast<int>(line)};
}

}  // namespace ecpair::eni::detail
