#include "element.hpp"

#include <algorithm>

#include "ecpair/common/log.hpp"

namespace ecpair::eni::detail {

Element::Element(const tinyxml2::XMLElement& xml, std::string path) : xml_(&xml), path_(std::move(path)) {}

void Element::fail(const std::string& message) const {
    throw LoadError(line(), path_, message);
}

void Element::fail_missing(std::string_view child_name) const {
    throw LoadError(line(), path_ + "/" + std::string(child_name), "required element is missing");
}

void Element::fail_attribute(std::string_view name, const std::string& message) const {
    throw LoadError(line(), path_ + "/@" + std::string(name), message);
}

void Element::remember(std::string_view name) const {
    if (std::find(read_names_.begin(), read_names_.end(), name) == read_names_.end()) {
        read_names_.emplace_back(name);
    }
}

std::optional<Element> Element::child(std::string_view name) const {
    remember(name);
    const std::string key(name);
    const auto* found = xml_->FirstChildElement(key.c_str());
    if (found == nullptr) return std::nullopt;
    return Element(*found, path_ + "/" + key);
}

Element Element::required_child(std::string_view name) const {
    if (auto found = child(name)) return std::move(*found);
    fail_missing(name);
}

std::vector<Element> Element::children(std::string_view name) const {
    remember(name);
    const std::string key(name);
    std::vector<Element> found;
    for (const auto* c = xml_->FirstChildElement(key.c_str()); c != nullptr; c = c->NextSiblingElement(key.c_str())) {
        found.emplace_back(*c, path_ + "/" + key + "[" + std::to_string(found.size() + 1) + "]");
    }
    return found;
}

void Element::log_unread_children() const {
    std::vector<std::string_view> reported;
    for (const auto* c = xml_->FirstChildElement(); c != nullptr; c = c->NextSiblingElement()) {
        const std::string_view child_name = c->Name();
        const bool read = std::find(read_names_.begin(), read_names_.end(), child_name) != read_names_.end();
        if (read || std::find(reported.begin(), reported.end(), child_name) != reported.end()) continue;
        reported.push_back(child_name);
        logger("eni")->debug("line {}: ignoring {}/{} (not used by ecpair)", c->GetLineNum(), path_, child_name);
    }
}

std::string Element::text() const {
    std::string collected;
    for (const auto* node = xml_->FirstChild(); node != nullptr; node = node->NextSibling()) {
        if (const auto* text_node = node->ToText()) collected += text_node->Value();
    }
    return std::string(trim(collected));
}

std::optional<bool> Element::optional_boolean(std::string_view name) const {
    if (auto c = child(name)) return c->boolean();
    return std::nullopt;
}

std::string Element::optional_text(std::string_view name) const {
    if (auto c = child(name)) return c->text();
    return {};
}

std::optional<std::string_view> Element::attribute(std::string_view name) const {
    const std::string key(name);
    const char* value = xml_->Attribute(key.c_str());
    if (value == nullptr) return std::nullopt;
    return std::string_view(value);
}

std::optional<bool> Element::attribute_boolean(std::string_view name) const {
    const auto text = attribute(name);
    if (!text) return std::nullopt;
    auto parsed = parse_boolean(*text);
    if (!parsed) fail_attribute(name, parsed.error());
    return *parsed;
}

}  // namespace ecpair::eni::detail
