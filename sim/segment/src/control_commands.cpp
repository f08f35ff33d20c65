// Executes parsed control requests on a Segment and formats the answers.
// The segment does the work and says why it refuses (FaultError); this file
// only maps requests to calls and results to response lines.

#include "ecpair/sim/control_commands.hpp"

#include <fmt/format.h>

#include "ecpair/sim/dc_report_format.hpp"
#include "ecpair/wire/al_status.hpp"

namespace ecpair::sim {

namespace {

std::string in_double_quotes(std::string_view text) {
    std::string out = "\"";
    for (const char c : text) {
        const auto byte = static_cast<unsigned char>(c);
        out += (byte < 0x20 || byte == 0x7F) ? ' ' : (c == '"' ? '\'' : c);
    }
    out += '"';
    return out;
}

std::string port_states(const Esc& esc) {
    std::string text;
    for (int p = 0; p < kPortCount; ++p) {
        if (!esc.port_implemented(p)) continue;
        if (!text.empty()) text += ',';
        text += fmt::format("{}:{}/{}", p, esc.physical_link(p) ? "up" : "down", esc.port_open(p) ? "open" : "closed");
    }
    return text;
}

// Per implemented port: invalid frames / RX errors / forwarded RX errors / lost links (0x0300-0x0313).
std::string port_errors(const Esc& esc) {
    const auto c = esc.read_memory(0x0300, 0x14);
    std::string text;
    for (int p = 0; p < kPortCount; ++p) {
        if (!esc.port_implemented(p)) continue;
        const auto i = static_cast<std::size_t>(p);
        if (!text.empty()) text += ',';
        text += fmt::format("{}:{}/{}/{}/{}", p, c[2 * i], c[2 * i + 1], c[8 + i], c[0x10 + i]);
    }
    return text;
}

std::string outcome(const Expected<void, FaultError>& result, std::string_view done) {
    return result ? control_ok(done) : control_error(result.error().message);
}

}  // namespace

std::string format_status(const Segment& segment) {
    const auto& c = segment.counters();
    const auto& main = c.sides[static_cast<std::size_t>(Side::Main)];
    const auto& red = c.sides[static_cast<std::size_t>(Side::Red)];

    std::string broken;
    for (std::size_t k = 0; k <= segment.slave_count(); ++k) {
        if (segment.topology().cable_after(k) && !segment.link_after_intact(k)) {
            broken += broken.empty() ? fmt::format("{}", k) : fmt::format(",{}", k);
        }
    }

    std::string text = fmt::format(
        "slaves={} main={} red={} in=MAIN:{},RED:{} out=MAIN:{},RED:{} destroyed={} lost_no_link={} "
        "lost_closed_port={} non_ecat_dropped={} unprocessable={} hop_limit={} epus_passed={} damaged_dropped={} "
        "broken={}",
        segment.slave_count(), segment.side_link(Side::Main) ? "up" : "down",
        segment.side_link(Side::Red) ? "up" : "down", main.frames_in, red.frames_in, main.frames_out, red.frames_out,
        c.destroyed_circulating, c.lost_no_link, c.lost_closed_port, c.non_ethercat_dropped, c.unprocessable,
        c.hop_limit_exceeded, c.epus_passed, c.damaged_dropped, broken.empty() ? "none" : broken);

    for (std::size_t position = 1; position <= segment.slave_count(); ++position) {
        const Esc& esc = segment.slave(position);
        const auto& d = esc.description();
        text += fmt::format(
            " | {} name={} vendor={:#010x} product={:#010x} addr={:#06x} alias={:#06x} al={} code={:#06x} powered={} "
            "unknown={} ports={} errors={} group={}",
            position, in_double_quotes(d.name), d.vendor_id, d.product_code, esc.station_address(), esc.station_alias(),
            wire::AlStatus{esc.al_status()}.to_string(), esc.al_status_code(), esc.powered() ? "yes" : "no",
            segment.is_unknown(position) ? "yes" : "no", port_states(esc), port_errors(esc), segment.group_of(position));
    }
    return control_ok(text);
}

std::string execute_control_request(Segment& segment, const ControlRequest& request) {
    const std::size_t k = request.position;
    switch (request.command) {
        case ControlCommand::Status: return format_status(segment);
        case ControlCommand::Help: return control_ok(control_usage());
        case ControlCommand::PowerOff: return outcome(segment.power_off(k), fmt::format("slave {} powered off", k));
        case ControlCommand::PowerOn: return outcome(segment.power_on(k), fmt::format("slave {} powered on", k));
        case ControlCommand::Break:
            return outcome(segment.break_link_after(k), fmt::format("link after slave {} broken", k));
        case ControlCommand::Repair:
            return outcome(segment.repair_link_after(k), fmt::format("link after slave {} repaired", k));
        case ControlCommand::InsertUnknown:
            return outcome(segment.insert_unknown_slave(k), fmt::format("unknown slave inserted as slave {}", k));
        case ControlCommand::RemoveUnknown:
            return outcome(segment.remove_unknown_slave(k), fmt::format("unknown slave {} removed", k));
        case ControlCommand::SetAlias:
            return outcome(
                segment.set_eeprom_alias(k, request.value),
                fmt::format("slave {} EEPROM alias {:#06x} (taken over at its next EEPROM load)", k, request.value));
        case ControlCommand::SetId:
            return outcome(segment.set_id_selector(k, request.value),
                           fmt::format("slave {} ID selector {:#06x}", k, request.value));
        case ControlCommand::GroupOff:
            return outcome(segment.set_group_power(request.group, false), fmt::format("group {} powered off", request.group));
        case ControlCommand::GroupOn:
            return outcome(segment.set_group_power(request.group, true), fmt::format("group {} powered on", request.group));
        case ControlCommand::PlugGroup:
            return outcome(segment.plug_group(request.group, request.at, request.port),
                           fmt::format("group {} plugged into slave {} port {}", request.group, request.at,
                                       port_letter(request.port)));
        case ControlCommand::UnplugGroup:
            return outcome(segment.unplug_group(request.group), fmt::format("group {} unplugged", request.group));
        // The number the plugged slave gets, read before the plug adds it
        // (the order in which a call's arguments are evaluated is unspecified).
        case ControlCommand::PlugUnknown: {
            const auto added_as = segment.slave_count() + 1;
            return outcome(segment.plug_unknown_slave(k, request.port),
                           fmt::format("unknown slave plugged into slave {} port {} as slave {}", k,
                                       port_letter(request.port), added_as));
        }
        case ControlCommand::PlugDuplicate: {
            const auto added_as = segment.slave_count() + 1;
            return outcome(segment.plug_duplicate(k, request.at, request.port),
                           fmt::format("a duplicate of slave {} plugged into slave {} port {} as slave {}", k,
                                       request.at, port_letter(request.port), added_as));
        }
        case ControlCommand::RefuseState: {
            const auto state = request.state == 0 ? std::nullopt
                                                  : std::optional<eni::SlaveState>(static_cast<eni::SlaveState>(request.state));
            return outcome(segment.refuse_states_from(k, state),
                           state ? fmt::format("slave {} refuses {} and above", k, eni::to_string(*state))
                                 : fmt::format("slave {} refuses no state", k));
        }
        case ControlCommand::SetSelector:
            return outcome(segment.set_legacy_id_selector(k, request.value),
                           fmt::format("slave {} ETG.1020 ID selector {} (read at its next power-on)", k, request.value));
        case ControlCommand::Emergency: {
            wire::CoeEmergency emergency;
            emergency.error_code = request.value;
            emergency.error_register = request.error_register;
            emergency.data = request.emergency_data;
            return outcome(segment.send_emergency(k, emergency),
                           fmt::format("slave {} sends CoE emergency 0x{:04x} (register 0x{:02x})", k, request.value,
                                       request.error_register));
        }
        case ControlCommand::FoePassword:
            return outcome(segment.set_foe_password(k, request.password),
                           request.password == 0 ? fmt::format("slave {} asks for no FoE password", k)
                                                 : fmt::format("slave {} asks for FoE password 0x{:08x}", k,
                                                               request.password));
        case ControlCommand::FoeBusy:
            return outcome(segment.set_foe_busy(k, request.value),
                           fmt::format("slave {} answers the next {} FoE data packet(s) BUSY", k, request.value));
        case ControlCommand::PortErrors:
            return outcome(segment.inject_rx_errors(k, request.port, request.count),
                           fmt::format("the next {} frame(s) arriving at slave {} port {} are damaged there", request.count,
                                       k, port_letter(request.port)));
        case ControlCommand::Impair:
            return control_error("impair acts on ecsim's cables, not on the segment: send it to a running ecsim");
        case ControlCommand::Dc:
            switch (request.dc) {
                case DcRequest::Text: return control_ok(format_dc_text(segment.dc_report(), segment));
                case DcRequest::Json: return control_ok(format_dc_json(segment.dc_report(), segment));
                case DcRequest::Reset:
                    segment.reset_dc_statistics();
                    return control_ok("DC worst deviation and missed SYNC0 edges reset");
            }
            break;
    }
    return control_error("unhandled command");
}

std::string handle_control_line(Segment& segment, std::string_view line) {
    const auto request = parse_control_request(line);
    if (!request) return control_error(request.error().message);
    return execute_control_request(segment, *request);
}

}  // namespace ecpair::sim
