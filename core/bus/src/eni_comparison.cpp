// Walks the configured slaves in ring order next to the scanned positions.
// A mandatory slave takes the next scanned position whatever sits there; a
// Hot-Connect group takes its positions only when the slave there matches
// the group's head, otherwise it is absent and takes none. Scanned slaves
// left over at the end are unexpected.

#include "ecpair/bus/eni_comparison.hpp"

#include <algorithm>
#include <numeric>

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

std::string_view identification_name(std::uint16_t ado) {
    return ado == kIdentificationAlias ? "station alias" : "explicit device ID";
}

// The identification the ENI asks for, with the value read at `found`.
std::optional<IdentificationCheck> identification_check(const eni::Slave& configured, const ScannedSlave* found,
                                                        const IdentificationReadings& readings) {
    const auto& wanted = configured.info.identification;
    if (!wanted || !wanted->value || *wanted->value == 0) return std::nullopt;
    IdentificationCheck check{wanted->ado, *wanted->value, std::nullopt};
    if (!found) return check;
    if (wanted->ado == kIdentificationAlias) {
        check.read = found->alias;
    } else if (found->position < readings.explicit_device_ids.size()) {
        check.read = readings.explicit_device_ids[found->position];
    }
    return check;
}

// Where a configured slave hangs: its selected PreviousPort, or the slave before it in ring order.
void set_previous(SlaveComparison& c, const eni::Slave& configured, const eni::Slave* ring_predecessor) {
    const auto& previous = configured.previous_ports;
    const auto selected = std::find_if(previous.begin(), previous.end(),
                                       [](const eni::PreviousPort& p) { return p.selected; });
    if (selected != previous.end()) {
        c.previous_station = selected->phys_addr;
        c.previous_port = selected->port;
    } else if (!previous.empty()) {
        c.previous_station = previous.front().phys_addr;
        c.previous_port = previous.front().port;
    } else if (ring_predecessor) {
        c.previous_station = ring_predecessor->info.phys_addr;
    }
}

SlaveMatch evaluate(const eni::Slave& configured, const ScannedSlave* found,
                    const std::optional<IdentificationCheck>& identification, bool optional) {
    if (!found) return optional ? SlaveMatch::Absent : SlaveMatch::Missing;
    if (!found->identity) return SlaveMatch::Unreadable;
    if (!identity_matches(configured.info, *found->identity)) return SlaveMatch::WrongIdentity;
    if (identification && identification->read != identification->expected) return SlaveMatch::WrongIdentification;
    return SlaveMatch::Match;
}

class Aligner {
public:
    Aligner(const ScanReport& report, const eni::EniConfig& eni, const IdentificationReadings& readings)
        : report_(report), eni_(eni), readings_(readings), ring_order_(eni.slaves.size()) {
        std::iota(ring_order_.begin(), ring_order_.end(), std::size_t{0});
        std::stable_sort(ring_order_.begin(), ring_order_.end(), [&eni](std::size_t a, std::size_t b) {
            return eni.slaves[a].info.ring_position < eni.slaves[b].info.ring_position;
        });
    }

    std::vector<SlaveComparison> run() {
        for (std::size_t k = 0; k < ring_order_.size();) {
            const auto& slave = eni_.slaves[ring_order_[k]];
            if (slave.hot_connect) {
                k += align_group(k, std::max<std::size_t>(1, slave.hot_connect->group_member_count));
            } else {
                take_position(k, false);
                ++k;
            }
        }
        for (; next_position_ < report_.slaves.size(); ++next_position_) {
            SlaveComparison c;
            c.position = static_cast<std::uint16_t>(next_position_);
            c.match = SlaveMatch::Unexpected;
            c.found = &report_.slaves[next_position_];
            if (last_present_) c.previous_station = last_present_->info.phys_addr;
            result_.push_back(c);
        }
        return std::move(result_);
    }

private:
    const ScannedSlave* found_at(std::size_t position) const {
        return position < report_.slaves.size() ? &report_.slaves[position] : nullptr;
    }

    SlaveComparison compare(std::size_t k, const ScannedSlave* found, bool optional) const {
        const std::size_t index = ring_order_[k];
        const auto& configured = eni_.slaves[index];
        SlaveComparison c;
        c.position = static_cast<std::uint16_t>(next_position_);
        c.configured = &configured;
        c.configured_index = index;
        c.found = found;
        c.optional = optional;
        c.identification = identification_check(configured, found, readings_);
        c.match = evaluate(configured, found, c.identification, optional);
        set_previous(c, configured, last_present_);
        return c;
    }

    // A configured slave that takes the next scanned position.
    void take_position(std::size_t k, bool optional) {
        result_.push_back(compare(k, found_at(next_position_), optional));
        last_present_ = &eni_.slaves[ring_order_[k]];
        ++next_position_;
    }

    // A Hot-Connect group of `members` slaves starting at ring-order index k;
    // returns how many configured slaves it covered.
    std::size_t align_group(std::size_t k, std::size_t members) {
        const std::size_t end = std::min(k + members, ring_order_.size());
        const auto head = compare(k, found_at(next_position_), true);
        if (head.match == SlaveMatch::Match) {
            for (std::size_t m = k; m < end; ++m) take_position(m, true);
        } else {
            for (std::size_t m = k; m < end; ++m) result_.push_back(compare(m, nullptr, true));
        }
        return end - k;
    }

    const ScanReport& report_;
    const eni::EniConfig& eni_;
    const IdentificationReadings& readings_;
    std::vector<std::size_t> ring_order_;
    std::vector<SlaveComparison> result_;
    std::size_t next_position_ = 0;
    const eni::Slave* last_present_ = nullptr;
};

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
            const auto& id = *identification;
            const auto read = id.read ? fmt::format("{}", *id.read) : std::string("nothing readable");
            return fmt::format("{}: wrong identification: {} {} (0x{:04x}) expected {}, read {}", where,
                               configured_text, identification_name(id.ado), id.ado, id.expected, read);
        }
        default:
            return fmt::format("{}: {}: configured {}, found {}", where, to_string(match), configured_text,
                               found_text);
    }
}

std::vector<SlaveComparison> compare_with_eni(const ScanReport& report, const eni::EniConfig& eni,
                                              const IdentificationReadings& readings) {
    return Aligner(report, eni, readings).run();
}

bool all_match(const std::vector<SlaveComparison>& comparisons) {
    return std::none_of(comparisons.begin(), comparisons.end(),
                        [](const SlaveComparison& c) { return c.is_mismatch(); });
}

}  // namespace ecpair::bus
