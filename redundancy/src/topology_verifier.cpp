#include "ecpair/redundancy/topology_verifier.hpp"

#include <algorithm>
#include <condition_variable>
#include <mutex>

#include "ecpair/bus/bus_scan.hpp"
#include "ecpair/bus/eni_comparison.hpp"
#include "ecpair/common/log.hpp"
#include "ecpair/redundancy/redundancy_events.hpp"

namespace ecpair::redundancy {

TopologyVerifier::~TopologyVerifier() = default;  // jthread joins

void TopologyVerifier::verify(std::vector<master::SlaveStateEntry> expected) {
    if (thread_.joinable()) {
        thread_.request_stop();
        thread_.join();
    }
    thread_ = std::jthread([this, expected = std::move(expected)](std::stop_token stop) { run(stop, expected); });
}

void TopologyVerifier::run(const std::stop_token& stop, const std::vector<master::SlaveStateEntry>& expected) {
    auto report = bus::scan_bus(bus_);
    for (int attempt = 1; !report && !stop.stop_requested(); ++attempt) {
        if (attempt == kAttempts) {
            logger("redundancy")->error("background scan after takeover failed {} times, the last: {}; the mirrored "
                                        "topology stays unverified",
                                        kAttempts, report.error().message);
            return;
        }
        logger("redundancy")->warn("background scan after takeover failed (attempt {} of {}): {}; again in {} ms",
                                   attempt, kAttempts, report.error().message, retry_after_.count());
        std::mutex mutex;
        std::condition_variable_any sleep;  // a wait that a stop request ends early
        std::unique_lock lock(mutex);
        sleep.wait_for(lock, stop, retry_after_, [] { return false; });
        if (stop.stop_requested()) return;
        report = bus::scan_bus(bus_);
    }
    if (!report) return;  // stopped
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
    events_.raise(events::kTopologyVerified, ok ? 1u : 0u, static_cast<std::uint32_t>(report->responding),
                  static_cast<std::uint32_t>(present));
}

}  // namespace ecpair::redundancy
