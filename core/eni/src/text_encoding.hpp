#pragma once
// Brings the raw bytes of an ENI file to UTF-8 before XML parsing.
// tinyxml2 does not transcode: it hands out the bytes as they are. TwinCAT and
// EC-Engineer declare ISO-8859-1, so a name like "Ausgänge" arrives as one
// byte 0xE4 that is not UTF-8. Transcoding the whole buffer first keeps every
// line number and gives the model valid UTF-8 strings.

#include <optional>
#include <string>
#include <string_view>

#include "ecpair/common/expected.hpp"

namespace ecpair::eni::detail {

// The encoding named in the XML declaration (`<?xml ... encoding="X"?>`), or
// nullopt when there is no declaration or it names none.
std::optional<std::string> declared_encoding(std::string_view document);

struct Utf8Text {
    std::string text;
    // Set when the bytes were not valid UTF-8 although nothing declared
    // ISO-8859-1, and were read as ISO-8859-1 anyway: the 1-based line of the
    // first invalid byte, for a warning.
    std::optional<int> reinterpreted_from_line;
};

// The document as UTF-8, or a message when the declared encoding is one the
// loader does not read (e.g. UTF-16).
Expected<Utf8Text, std::string> to_utf8(std::string_view document);

}  // namespace ecpair::eni::detail
