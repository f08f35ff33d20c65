// compare_with_eni is match_topology with the readings taken beforehand;
// describe() is the mismatch descriptor as one line.

#include "ecpair/bus/eni_comparison.hpp"

#include <algorithm>

#include <fmt/format.h>

#include "ecpair/bus/topology_match.hpp"

namespace ecpair::bus {
namespace {

std::string identity_text(std::uint32_t vendor, std::uint32_t product, std::uint32_t revision,
                          std::uint32_t serial) {
    return fmt::format("vendor 0x{:08x} product 0x{:08x} revision 0x{:08x} serial {}", vendor, product,
                       revision, serial);
}

std::string identification_name(std::uint16_t ado) {
    if (ado == kIdentificationAlias) return "station alias";
    if (ado == kIdentificationExplicitId) return "explicit device ID";
    return ado >= 0x1000 ? "input word" : "register";
}

}  // namespace

std::string_view to_string(SlaveMatch match) {
    switch (match) {
        case SlaveMatch::Match: return "match";
        case SlaveMatch::WrongIdentity: return "wrong identity";
        case SlaveMatch::WrongIdentification: return "wrong identification";
        case SlaveMatch::Missing: return "missing";
        case SlaveMatch::Absent: return "absent (optional)";
        case SlaveMatch::Unexpected: return "unexpected";
        case SlaveMatch::Unreadable: return "unreadable";
    }
    return "?";
}

std::string SlaveComparison::describe() const {
    std::string where = fmt::format("position {}", position);
    if (previous_station) {
        where += fmt::format(" (after station {}", *previous_station);
        if (previous_port) where += fmt::format(" port {}", *previous_port);
        where += ")";
    }
    const auto configured_text = configured
        ? fmt::format("'{}' {}", configured->info.name,
                      identity_text(configured->info.vendor_id, configured->info.product_code,
                                    configured->info.revision_no, configured->info.serial_no.value_or(0)))
        : std::string("nothing");
    const auto found_text = found && found->identity
        ? identity_text(found->identity->vendor_id, found->identity->product_code, found->identity->revision_no,
                        found->identity->serial_no)
        : std::string(found ? "a slave with unreadable SII" : "nothing");
    switch (match) {
        case SlaveMatch::Match: return fmt::format("{}: {} as configured", where, configured_text);
        case SlaveMatch::Missing: return fmt::format("{}: configured {}, found nothing", where, configured_text);
        case SlaveMatch::Absent:
            return fmt::format("{}: optional {} is absent", where, configured_text);
        case SlaveMatch::WrongIdentification: {
            if (!identification) {
                return fmt::format("{}: wrong identification: {}: its IdentifyCmds do not validate", where,
                                   configured_text);
            }
            const auto& id = *identification;
            const auto read = id.read ? fmt::format("{}", *id.read) : std::string("nothing readable");
            return fmt::format("{}: wrong identification: {} {} (0x{:04x}) expected {}, read {}", where,
                               configured_text, identification_name(id.ado), id.ado, id.expected, read);
        }
        default: {
            auto text = fmt::format("{}: {}: configured {}, found {}", where, to_string(match), configured_text,
                                    found_text);
            if (found && match == SlaveMatch::Unexpected) text += fmt::format(" at station address {}", found->station_address);
            if (!note.empty()) text += " (" + note + ")";
            return text;
        }
    }
}

std::vector<SlaveComparison> compare_with_eni(const ScanReport& report, const eni::EniConfig& eni,
                                              const IdentificationReadings& readings) {
    ReadingsProbe probe(readings);
    return match_topology(report, eni, eni::HotConnectGroups::of(eni), probe).comparisons;
}

bool all_match(const std::vector<SlaveComparison>& comparisons) {
    return std::none_of(comparisons.begin(), comparisons.end(),
                        [](const SlaveComparison& c) { return c.is_mismatch(); });
}

}  // namespace ecpair::bus
