#include "ecpair/bus/eni_comparison.hpp"

#include <algorithm>

#include <fmt/format.h>

namespace ecpair::bus {
namespace {

bool identity_matches(const eni::SlaveInfo& configured, const SlaveIdentity& found) {
    if (configured.vendor_id != found.vendor_id || configured.product_code != found.product_code ||
        configured.revision_no != found.revision_no) {
        return false;
    }
    // A serial of 0 in the ENI means "any device of this type".
    return !configured.serial_no || *configured.serial_no == 0 || *configured.serial_no == found.serial_no;
}

std::string identity_text(std::uint32_t vendor, std::uint32_t product, std::uint32_t revision,
                          std::uint32_t serial) {
    return fmt::format("vendor 0x{:08x} product 0x{:08x} revision 0x{:08x} serial {}", vendor, product,
                       revision, serial);
}

}  // namespace

std::string_view to_string(SlaveMatch match) {
    switch (match) {
        case SlaveMatch::Match: return "match";
        case SlaveMatch::WrongIdentity: return "wrong identity";
        case SlaveMatch::Missing: return "missing";
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
        default:
            return fmt::format("{}: {}: configured {}, found {}", where, to_string(match), configured_text,
                               found_text);
    }
}

std::vector<SlaveComparison> compare_with_eni(const ScanReport& report, const eni::EniConfig& eni) {
    std::vector<SlaveComparison> result;
    const std::size_t positions = std::max(report.slaves.size(), eni.slaves.size());
    for (std::size_t i = 0; i < positions; ++i) {
        SlaveComparison c;
        c.position = static_cast<std::uint16_t>(i);
        c.configured = i < eni.slaves.size() ? &eni.slaves[i] : nullptr;
        c.found = i < report.slaves.size() ? &report.slaves[i] : nullptr;
        if (c.configured) {
            const auto& previous = c.configured->previous_ports;
            const auto selected = std::find_if(previous.begin(), previous.end(),
                                               [](const eni::PreviousPort& p) { return p.selected; });
            if (selected != previous.end()) {
                c.previous_station = selected->phys_addr;
                c.previous_port = selected->port;
            } else if (!previous.empty()) {
                c.previous_station = previous.front().phys_addr;
                c.previous_port = previous.front().port;
            } else if (i > 0) {
                c.previous_station = eni.slaves[i - 1].info.phys_addr;
            }
        }
        if (!c.found) {
            c.match = SlaveMatch::Missing;
        } else if (!c.configured) {
            c.match = SlaveMatch::Unexpected;
        } else if (!c.found->identity) {
            c.match = SlaveMatch::Unreadable;
        } else {
            c.match = identity_matches(c.configured->info, *c.found->identity) ? SlaveMatch::Match
                                                                               : SlaveMatch::WrongIdentity;
        }
        result.push_back(c);
    }
    return result;
}

bool all_match(const std::vector<SlaveComparison>& comparisons) {
    return std::all_of(comparisons.begin(), comparisons.end(),
                       [](const SlaveComparison& c) { return c.match == SlaveMatch::Match; });
}

}  // namespace ecpair::bus
