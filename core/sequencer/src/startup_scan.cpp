// The startup scan (see the header): scan, explicit IDs where asked for,
// comparison, then presence and position shifts per configured slave. Every
// mismatch is logged with its descriptor.

#include "ecpair/sequencer/startup_scan.hpp"

#include <algorithm>

#include "ecpair/common/bytes.hpp"
#include "ecpair/common/log.hpp"
#include "ecpair/sequencer/transition_plan.hpp"
#include "ecpair/wire/al_status.hpp"
#include "ecpair/wire/esc_registers.hpp"

namespace ecpair::sequencer {
namespace {

constexpr std::uint8_t kIdRequest = 0x20;

bool asks_for_explicit_id(const eni::EniConfig& eni) {
    return std::any_of(eni.slaves.begin(), eni.slaves.end(), [](const eni::Slave& s) {
        const auto& id = s.info.identification;
        return id && id->ado == bus::kIdentificationExplicitId && id->value && *id->value != 0;
    });
}

}  // namespace

std::vector<const bus::SlaveComparison*> ScanOutcome::mismatches() const {
    std::vector<const bus::SlaveComparison*> result;
    for (const auto& c : comparisons) {
        if (c.is_mismatch()) result.push_back(&c);
    }
    return result;
}

std::optional<std::uint16_t> read_explicit_device_id(bus::BusAccess& bus, Clock& clock, std::uint16_t position,
                                                     std::chrono::milliseconds timeout, std::stop_token stop) {
    const auto slave = bus::SlaveAddress::position(position);
    auto status = bus::read_register(bus, slave, wire::reg::kAlStatus, 1);
    if (!status || status->wkc != 1 || status->data.empty()) return std::nullopt;
    const std::uint8_t state = wire::AlStatus{status->data[0]}.state();

    std::optional<std::uint16_t> id;
    if (auto asked = bus::write_register(bus, slave, wire::reg::kAlControl, {static_cast<std::uint8_t>(state | kIdRequest), 0});
        asked && asked->wkc == 1) {
        const auto deadline = clock.now() + timeout;
        while (!stop.stop_requested()) {
            auto loaded = bus::read_register(bus, slave, wire::reg::kAlStatus, 6);
            if (loaded && loaded->wkc == 1 && loaded->data.size() >= 6 && wire::AlStatus{loaded->data[0]}.id_loaded()) {
                id = load_le<std::uint16_t>(loaded->data, 4);
                break;
            }
            if (clock.now() >= deadline) break;
            clock.sleep_for(kPollInterval, stop);
        }
    }
    // Restore: the plain state, without the ID request.
    (void)bus::write_register(bus, slave, wire::reg::kAlControl, {state, 0});
    if (!id) logger("sequencer")->warn("position {}: no explicit device ID within {} ms", position, timeout.count());
    return id;
}

Expected<ScanOutcome, bus::BusError> StartupScan::run(const eni::EniConfig& eni, std::stop_token stop) {
    auto report = bus::scan_bus(bus_);
    if (!report) return unexpected(std::move(report).error());

    ScanOutcome outcome;
    outcome.report = std::move(report).value();
    if (asks_for_explicit_id(eni)) {
        for (const auto& slave : outcome.report.slaves) {
            outcome.readings.explicit_device_ids.push_back(
                read_explicit_device_id(bus_, clock_, slave.position, kExplicitIdTimeout, stop));
        }
    }
    outcome.comparisons = bus::compare_with_eni(outcome.report, eni, outcome.readings);
    outcome.matches = bus::all_match(outcome.comparisons);

    outcome.present.assign(eni.slaves.size(), true);
    outcome.position_shift.assign(eni.slaves.size(), 0);
    for (const auto& c : outcome.comparisons) {
        if (c.configured_index && c.match == bus::SlaveMatch::Absent) outcome.present[*c.configured_index] = false;
    }
    std::uint16_t absent_so_far = 0;
    for (const auto index : ring_order(eni)) {
        outcome.position_shift[index] = absent_so_far;
        if (!outcome.present[index]) ++absent_so_far;
    }

    auto log = logger("sequencer");
    log->info("startup scan: {} slave(s) found, {} configured: {}", outcome.report.responding, eni.slaves.size(),
              outcome.matches ? "bus matches the ENI" : "BUS MISMATCH");
    for (const auto& c : outcome.comparisons) {
        if (c.is_mismatch()) {
            log->error("bus mismatch: {}", c.describe());
        } else if (c.match == bus::SlaveMatch::Absent) {
            log->info("{}", c.describe());
        }
    }
    return outcome;
}

}  // namespace ecpair::sequencer
