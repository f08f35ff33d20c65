#include "ecpair/sequencer/bus_identification_probe.hpp"

#include "ecpair/common/bytes.hpp"
#include "ecpair/common/log.hpp"
#include "ecpair/sequencer/init_cmd_runner.hpp"
#include "ecpair/sequencer/startup_scan.hpp"

namespace ecpair::sequencer {

std::optional<std::uint16_t> BusIdentificationProbe::read(std::uint16_t position, const eni::IdentificationSpec& spec) {
    if (spec.mode == eni::IdentificationMode::ExplicitDeviceId) {
        const auto found = explicit_ids_.find(position);
        if (found != explicit_ids_.end()) return found->second;
        const auto id = read_explicit_device_id(bus_, clock_, position, kExplicitIdTimeout, stop_);
        explicit_ids_.emplace(position, id);
        return id;
    }
    const auto key = std::make_pair(position, spec.ado);
    const auto found = registers_.find(key);
    if (found != registers_.end()) return found->second;
    std::optional<std::uint16_t> value;
    if (auto r = bus::read_register(bus_, bus::SlaveAddress::position(position), spec.ado, 2); r && r->wkc == 1) {
        value = load_le<std::uint16_t>(r->data, 0);
    }
    registers_.emplace(key, value);
    return value;
}

bool BusIdentificationProbe::identify_cmds_pass(std::uint16_t position, std::size_t head) {
    const auto& slave = eni_.slaves[head];
    if (!slave.hot_connect || slave.hot_connect->identify_cmds.empty()) return true;
    const auto key = std::make_pair(position, head);
    if (const auto found = identify_cmds_.find(key); found != identify_cmds_.end()) return found->second;

    CommandContext context;
    context.owner = slave.info.name;
    context.station = slave.info.phys_addr;
    context.slave_index = head;
    // The IdentifyCmds address the head where the ENI has it; it sits at `position`.
    context.position_shift = static_cast<std::uint16_t>(slave.info.ring_position - position);
    InitCmdRunner runner(bus_, clock_);
    bool pass = true;
    for (const auto& cmd : slave.hot_connect->identify_cmds) {
        if (auto r = runner.run(cmd, context, stop_); !r) {
            logger("sequencer")->info("position {}: not group '{}': {}", position, slave.hot_connect->group_name,
                                      r.error().describe());
            pass = false;
            break;
        }
    }
    identify_cmds_.emplace(key, pass);
    return pass;
}

}  // namespace ecpair::sequencer
