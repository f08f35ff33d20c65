#pragma once
// Element: one XML element of the ENI as the readers see it. It knows its
// element path (/EtherCATConfig/Config/Slave[2]/Info) and source line, so any
// reader can fail *at* an element with fail() and the error says where.
//
// Paths: an element fetched with children() (the repeating ones: Slave,
// InitCmd, Cmd, Variable...) carries its 1-based index among same-named
// siblings, even when it is the only one; an element fetched with child() or
// required_child() (the single ones: Info, PhysAddr...) carries none.
// Attributes appear as /@Name.
//
// Every child name a reader asks for is remembered; log_unread_children()
// then reports the rest at debug level (unknown elements are never errors).

#include <concepts>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <tinyxml2.h>

#include "load_error.hpp"
#include "values.hpp"

namespace ecpair::eni::detail {

class Element {
public:
    Element(const tinyxml2::XMLElement& xml, std::string path);

    const std::string& path() const { return path_; }
    int line() const { return xml_->GetLineNum(); }
    std::string_view name() const { return xml_->Name(); }

    [[noreturn]] void fail(const std::string& message) const;
    // Fails with "required element is missing" at the path of the absent child.
    [[noreturn]] void fail_missing(std::string_view child_name) const;

    // ---- children
    std::optional<Element> child(std::string_view name) const;
    Element required_child(std::string_view name) const;  // fails when missing
    std::vector<Element> children(std::string_view name) const;
    bool has_child(std::string_view name) const { return child(name).has_value(); }
    void log_unread_children() const;

    // ---- this element's own text
    // All text and CDATA content, surrounding whitespace removed (inner
    // whitespace and newlines stay: "Slave_1001 [RDM\n]").
    std::string text() const;

    template <std::integral T>
    T number(Negative negative = Negative::Reject) const {
        return value(parse_number<T>(text(), negative));
    }
    bool boolean() const { return value(parse_boolean(text())); }
    std::vector<std::uint8_t> hex_binary() const { return value(parse_hex_binary(text())); }

    // Unwraps a parser's result, failing at this element with its message.
    template <class T>
    T value(ValueResult<T> result) const {
        if (!result) fail(result.error());
        return std::move(*result);
    }

    // ---- children's text, the common case
    template <std::integral T>
    T required_number(std::string_view name, Negative negative = Negative::Reject) const {
        return required_child(name).number<T>(negative);
    }
    template <std::integral T>
    std::optional<T> optional_number(std::string_view name, Negative negative = Negative::Reject) const {
        if (auto c = child(name)) return c->number<T>(negative);
        return std::nullopt;
    }
    std::optional<bool> optional_boolean(std::string_view name) const;
    std::string optional_text(std::string_view name) const;  // "" when absent

    // ---- attributes
    std::optional<std::string_view> attribute(std::string_view name) const;
    std::optional<bool> attribute_boolean(std::string_view name) const;
    template <std::integral T>
    std::optional<T> attribute_number(std::string_view name) const {
        const auto text = attribute(name);
        if (!text) return std::nullopt;
        auto parsed = parse_number<T>(*text);
        if (!parsed) fail_attribute(name, parsed.error());
        return *parsed;
    }
    [[noreturn]] void fail_attribute(std::string_view name, const std::string& message) const;

private:
    void remember(std::string_view name) const;

    const tinyxml2::XMLElement* xml_;
    std::string path_;
    mutable std::vector<std::string> read_names_;
};

}  // namespace ecpair::eni::detail
