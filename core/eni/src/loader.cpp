// load_eni_file / load_eni_string: the loader's front door.
//
//   raw bytes --FNV-1a--> content_hash
//             --to_utf8--> UTF-8 text (ISO-8859-1 transcoded, see text_encoding.hpp)
//             --tinyxml2--> DOM (syntax errors carry tinyxml2's line)
//             --readers--> immutable EniConfig
//
// Readers throw LoadError at the offending element; it is caught here, once,
// and becomes an EniError with file, line and element path. Nothing else is
// thrown for bad input, so a fuzzed document can only load or fail cleanly.

#include "ecpair/eni/loader.hpp"

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>

#include <fmt/format.h>
#include <tinyxml2.h>

#include "ecpair/common/log.hpp"
#include "readers.hpp"
#include "text_encoding.hpp"

namespace ecpair::eni {
namespace {

using detail::Element;

constexpr std::uintmax_t kMaxFileSize = 64u * 1024u * 1024u;  // real ENIs stay below 1 MB

std::uint64_t fnv1a64(std::string_view bytes) {
    std::uint64_t hash = 0xcbf29ce484222325ull;
    for (const char c : bytes) {
        hash ^= static_cast<unsigned char>(c);
        hash *= 0x100000001b3ull;
    }
    return hash;
}

std::string describe_xml_error(const tinyxml2::XMLDocument& document) {
    std::string what;
    switch (document.ErrorID()) {
        case tinyxml2::XML_ERROR_EMPTY_DOCUMENT: what = "the document has no element"; break;
        case tinyxml2::XML_ERROR_MISMATCHED_ELEMENT: what = "a closing tag does not match its opening tag"; break;
        case tinyxml2::XML_ERROR_PARSING_ELEMENT: what = "malformed element"; break;
        case tinyxml2::XML_ERROR_PARSING_ATTRIBUTE: what = "malformed attribute"; break;
        case tinyxml2::XML_ERROR_PARSING_TEXT: what = "malformed text"; break;
        case tinyxml2::XML_ERROR_PARSING_CDATA: what = "malformed CDATA section"; break;
        case tinyxml2::XML_ERROR_PARSING_COMMENT: what = "malformed comment"; break;
        case tinyxml2::XML_ERROR_PARSING_DECLARATION: what = "malformed declaration"; break;
        case tinyxml2::XML_ERROR_PARSING_UNKNOWN: what = "malformed <! ... > construct"; break;
        // tinyxml2's catch-all when a child fails without a reason of its own:
        // in practice an element left open when the file ends.
        case tinyxml2::XML_ERROR_PARSING: what = "an element is not closed (or the file ends early)"; break;
        case tinyxml2::XML_ELEMENT_DEPTH_EXCEEDED:
            what = fmt::format("elements nest deeper than {} levels", TINYXML2_MAX_ELEMENT_DEPTH);
            break;
        default: what = document.ErrorName(); break;
    }
    // ErrorStr() is "Error=... Line number=N: <detail>"; keep the detail.
    const std::string_view full = document.ErrorStr();
    const auto line_part = full.find("Line number=");
    const auto detail_at = line_part == std::string_view::npos ? line_part : full.find(": ", line_part);
    if (detail_at != std::string_view::npos) what += " (" + std::string(full.substr(detail_at + 2)) + ")";
    return "not well-formed XML: " + what;
}

void read_document(const Element& root, EniConfig& config) {
    if (root.name() != "EtherCATConfig" && root.name() != "EncryptedEtherCATConfig") {
        root.fail(fmt::format("the root element is <{}>, expected <EtherCATConfig> (or <EncryptedEtherCATConfig>)",
                              root.name()));
    }
    config.root_element = std::string(root.name());
    if (const auto version = root.attribute("Version")) config.version = std::string(*version);

    const auto config_element = root.required_child("Config");
    config.master = detail::read_master(config_element.required_child("Master"));
    std::vector<Element> slave_elements;
    std::vector<Element> passive_elements;
    const auto all_slave_elements = config_element.children("Slave");
    for (std::size_t i = 0; i < all_slave_elements.size(); ++i) {
        const auto& slave = all_slave_elements[i];
        if (detail::is_passive_slave(slave)) {
            auto passive = detail::read_passive_slave(slave, i);
            logger("eni")->warn("{}:{}: {}: '{}' has no PhysAddr, AutoIncAddr or InitCmds: taken as a passive terminal "
                                "(no ESC: no address, no process data, not counted in the ring)",
                                config.source_path, slave.line(), slave.path(), passive.name);
            config.passive_slaves.push_back(std::move(passive));
            passive_elements.push_back(slave);
            continue;
        }
        config.slaves.push_back(detail::read_slave(slave));
        slave_elements.push_back(slave);
    }
    detail::check_slaves(config.slaves, slave_elements);
    detail::check_passive_slaves(config.passive_slaves, passive_elements, config.slaves);
    detail::check_register_init_cmds(config, root, config_element, slave_elements);
    for (const auto& cyclic : config_element.children("Cyclic")) config.cyclic.push_back(detail::read_cyclic(cyclic));
    if (const auto image = config_element.child("ProcessImage")) {
        config.process_image = detail::read_process_image(*image);
    }
    config_element.log_unread_children();
    root.log_unread_children();
}

EniError error_at(const std::string& file, int line, std::string path, std::string message) {
    return EniError{file, line, std::move(path), std::move(message)};
}

}  // namespace

std::string EniError::describe() const {
    std::string out = file;
    if (line > 0) out += ":" + std::to_string(line);
    out += ": ";
    if (!element_path.empty()) out += element_path + ": ";
    return out + message;
}

EniResult load_eni_string(std::string_view xml, const std::string& name) {
    auto config = std::make_shared<EniConfig>();
    config->source_path = name;
    config->content_hash = fnv1a64(xml);

    auto utf8 = detail::to_utf8(xml);
    if (!utf8) return unexpected(error_at(name, 1, "", utf8.error()));
    if (utf8->reinterpreted_from_line) {
        logger("eni")->warn("{}:{}: not valid UTF-8 and no encoding declared: reading the file as ISO-8859-1", name,
                            *utf8->reinterpreted_from_line);
    }

    tinyxml2::XMLDocument document;
    if (document.Parse(utf8->text.data(), utf8->text.size()) != tinyxml2::XML_SUCCESS) {
        return unexpected(error_at(name, document.ErrorLineNum(), "", describe_xml_error(document)));
    }
    const auto* root = document.RootElement();
    if (root == nullptr) return unexpected(error_at(name, 0, "", "the document has no root element"));

    try {
        read_document(Element(*root, "/" + std::string(root->Name())), *config);
    } catch (const detail::LoadError& e) {
        std::string message = e.what();
        // An encrypted body may fail anywhere; the register checks say so where they see it.
        if (std::string_view(root->Name()) == "EncryptedEtherCATConfig" &&
            message.find("is encrypted") == std::string::npos) {
            message += " (the root is <EncryptedEtherCATConfig>: if the file is encrypted, export it without encryption)";
        }
        return unexpected(error_at(name, e.line(), e.element_path(), std::move(message)));
    }
    logger("eni")->debug("{}: loaded {} slave(s), {} cyclic section(s)", name, config->slaves.size(),
                         config->cyclic.size());
    return std::shared_ptr<const EniConfig>(std::move(config));
}

EniResult load_eni_file(const std::string& path) {
    std::error_code ec;
    const auto status = std::filesystem::status(path, ec);
    if (ec || !std::filesystem::exists(status)) {
        const std::string reason = ec ? ec.message() : std::string(std::strerror(ENOENT));
        return unexpected(error_at(path, 0, "", "cannot open the file: " + reason));
    }
    if (!std::filesystem::is_regular_file(status)) {
        return unexpected(error_at(path, 0, "", "cannot read the file: it is not a regular file"));
    }
    const auto size = std::filesystem::file_size(path, ec);
    if (ec) return unexpected(error_at(path, 0, "", "cannot read the file: " + ec.message()));
    if (size > kMaxFileSize) {
        return unexpected(error_at(path, 0, "", fmt::format("the file is {} bytes, more than the {} an ENI may have",
                                                            size, kMaxFileSize)));
    }
    std::ifstream in(path, std::ios::binary);
    if (!in) return unexpected(error_at(path, 0, "", std::string("cannot open the file: ") + std::strerror(errno)));
    std::string bytes(static_cast<std::size_t>(size), '\0');
    in.read(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    if (in.gcount() != static_cast<std::streamsize>(bytes.size())) {
        return unexpected(error_at(path, 0, "", std::string("cannot read the file: ") + std::strerror(errno)));
    }
    return load_eni_string(bytes, path);
}

}  // namespace ecpair::eni
