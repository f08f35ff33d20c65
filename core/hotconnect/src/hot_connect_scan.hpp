#pragma once
// The scan of a topology change: what bus::scan_bus reads, but a slave that
// shows the station address of a configured slave already on the bus is
// taken as that slave without reading its SII again (it was identified when
// it joined, and its identification is not asked again either: an explicit
// device ID request or an IdentifyCmd could disturb a slave in OP). New
// slaves -- after a power-on their station address is 0 -- are read in full.
// Two reads per known slave: 0x0010 (station address, alias) and
// 0x0110-0x0135 (DL status, AL status and code).

#include <map>
#include <stop_token>
#include <vector>

#include "ecpair/bus/bus_access.hpp"
#include "ecpair/bus/bus_scan.hpp"
#include "ecpair/bus/topology_match.hpp"
#include "ecpair/eni/model.hpp"
#include "ecpair/sequencer/bus_identification_probe.hpp"
#include "ecpair/sequencer/clock.hpp"

namespace ecpair::hotconnect {

struct HotConnectScan {
    bus::ScanReport report;
    // Bus positions of configured slaves taken from what is known (ENI index by position).
    std::map<std::uint16_t, std::size_t> known;
};

// `present[i]`: ENI slave i is on the bus and identified.
Expected<HotConnectScan, bus::BusError> scan_for_hot_connect(bus::BusAccess& bus, const eni::EniConfig& eni,
                                                             const std::vector<bool>& present);

// The probe of a topology change: known positions answer with what the ENI
// expects of them, new ones are asked on the bus.
class HotConnectProbe final : public bus::IdentificationProbe {
public:
    HotConnectProbe(const HotConnectScan& scan, const eni::EniConfig& eni, sequencer::BusIdentificationProbe& bus_probe)
        : scan_(scan), eni_(eni), bus_probe_(bus_probe) {}
    std::optional<std::uint16_t> read(std::uint16_t position, const eni::IdentificationSpec& spec) override;
    bool identify_cmds_pass(std::uint16_t position, std::size_t head) override;

private:
    const HotConnectScan& scan_;
    const eni::EniConfig& eni_;
    sequencer::BusIdentificationProbe& bus_probe_;
};

}  // namespace ecpair::hotconnect
