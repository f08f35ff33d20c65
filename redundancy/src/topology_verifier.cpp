#include "ecpair/redundancy/topology_verifier.hpp"

#include <algorithm>

#include "ecpair/bus/bus_scan.hpp"
#include "ecpair/bus/eni_comparison.hpp"
#include "ecpair/common/log.hpp"

namespace ecpair::redundancy {

TopologyVerifier::~TopologyVerifier() = default;  // jthread joins

void TopologyVerifier::verify(std::vector<master::SlaveStateEntry> expected) {
    if (thread_.joinable()) thread_.join();
    thread_ = std::jthread([this, expected = std::move(expected)] { run(expected); });
}

void TopologyVerifier::run(const std::vector<master::SlaveStateEntry>& expected) {
    auto report = bus::scan_bus(bus_);
    if (!report) {
        logger("redundancy")->warn("background scan after takeover failed: {}", report.error().message);
        return;
    }
    const auto present = static_cast<std::size_t>(
        std::count_if(expected.begin(), expected.end(), [](const master::SlaveStateEntry& e) { return e.present; }));
    const auto comparisons = bus::compare_with_eni(*report, *eni_);
    const bool identities = std::all_of(comparisons.begin(), comparisons.end(), [](const bus::SlaveComparison& c) {
        return !c.is_mismatch() || c.match == bus::SlaveMatch::Missing;
    });
    const bool ok = report->responding == present && identities;
    if (ok) {
        logger("redundancy")->info("background scan confirms the mirrored topology: {} slave(s)", present);
    } else {
        logger("redundancy")->error("background scan: {} slave(s) answer, the mirrored image has {} present", report->responding,
                                    present);
        for (const auto& c : comparisons) {
            if (c.is_mismatch()) logger("redundancy")->error("  {}", c.describe());
        }
    }
    events_.raise(master::EventKind::TopologyVerified, ok ? 1u : 0u, static_cast<std::uint32_t>(report->responding),
                  static_cast<std::uint32_t>(present));
}

}  // namespace ecpair::redundancy
