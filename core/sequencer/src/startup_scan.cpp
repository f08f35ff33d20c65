// The startup scan (see the header): scan, explicit IDs where asked for,
// comparison, then presence and position shifts per configured slave. Every
// mismatch is logged with its descriptor.

#include "ecpair/sequencer/startup_scan.hpp"

#include <algorithm>

#include "ecpair/common/bytes.hpp"
#include "ecpair/common/log.hpp"
#include "ecpair/eni/hot_connect_groups.hpp"
#include "ecpair/sequencer/bus_identification_probe.hpp"
#include "ecpair/sequencer/transition_plan.hpp"
#include "ecpair/wire/al_status.hpp"
#include "ecpair/wire/esc_registers.hpp"

namespace ecpair::sequencer {
namespace {

constexpr std::uint8_t kIdRequest = 0x20;

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
    const auto groups = eni::HotConnectGroups::of(eni);
    BusIdentificationProbe probe(bus_, clock_, eni, stop);
    auto match = bus::match_topology(outcome.report, eni, groups, probe);
    outcome.readings.explicit_device_ids.assign(outcome.report.slaves.size(), std::nullopt);
    for (const auto& [position, id] : probe.explicit_ids()) {
        if (position < outcome.readings.explicit_device_ids.size()) outcome.readings.explicit_device_ids[position] = id;
    }
    outcome.comparisons = match.comparisons;
    outcome.matches = !match.blocking();

    // Mandatory slaves take part whatever the scan said (a mismatch stops the
    // start anyway); an optional group only when it is present as configured.
    outcome.present.assign(eni.slaves.size(), true);
    for (std::size_t i = 0; i < eni.slaves.size(); ++i) {
        if (groups.is_optional(i)) outcome.present[i] = match.groups[groups.group_of(i)] == bus::GroupState::Present;
    }
    outcome.position_shift.assign(eni.slaves.size(), 0);
    std::uint16_t absent_so_far = 0;
    for (const auto index : ring_order(eni)) {
        const auto& at = match.position[index];
        outcome.position_shift[index] =
            at && outcome.present[index] ? static_cast<std::uint16_t>(eni.slaves[index].info.ring_position - *at)
                                         : absent_so_far;
        if (!outcome.present[index]) ++absent_so_far;
    }
    outcome.groups = std::move(match.groups);

    auto log = logger("sequencer");
    log->info("startup scan: {} slave(s) found, {} configured: {}", outcome.report.responding, eni.slaves.size(),
              outcome.matches ? "bus matches the ENI" : "BUS MISMATCH");
    for (const auto& c : outcome.comparisons) {
        if (c.is_mismatch() && (c.match == bus::SlaveMatch::Unexpected || !c.optional)) {
            log->error("bus mismatch: {}", c.describe());
        } else if (c.is_mismatch()) {
            log->warn("optional group refused: {}", c.describe());
        } else if (c.match == bus::SlaveMatch::Absent) {
            log->info("{}", c.describe());
        }
    }
    return outcome;
}

}  // namespace ecpair::sequencer
