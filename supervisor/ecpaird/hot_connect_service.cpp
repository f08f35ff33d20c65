#include "hot_connect_service.hpp"

#include <fmt/format.h>

#include "ecpair/wire/al_status.hpp"

namespace ecpair::daemon {
namespace {

control::Response refused(const hotconnect::OperationFailure& failure) {
    control::Response r;
    r.set_ok(false);
    r.set_error(fmt::format("{}: {}", hotconnect::to_string(failure.code), failure.message));
    return r;
}

control::Response accepted() {
    control::Response r;
    r.set_ok(true);
    return r;
}

std::string identification_text(const eni::IdentificationSpec& id) {
    switch (id.mode) {
        case eni::IdentificationMode::None: return "none";
        case eni::IdentificationMode::StationAlias: return fmt::format("station alias {}", id.value);
        case eni::IdentificationMode::ExplicitDeviceId: return fmt::format("explicit device ID {}", id.value);
        case eni::IdentificationMode::InputWord: return fmt::format("input word at 0x{:04x} = {}", id.ado, id.value);
        case eni::IdentificationMode::Register: return fmt::format("register 0x{:04x} = {}", id.ado, id.value);
    }
    return "?";
}

void set_port(control::HotConnectPort& out, const hotconnect::PortRef& port) {
    out.set_station(port.station);
    out.set_port(std::string(1, static_cast<char>('A' + port.port)));
}

std::optional<int> port_of(const std::string& letter) {
    if (letter.size() != 1) return std::nullopt;
    const char c = static_cast<char>(std::toupper(static_cast<unsigned char>(letter[0])));
    if (c < 'A' || c > 'D') return std::nullopt;
    return c - 'A';
}

}  // namespace

void HotConnectService::fill_summary(control::HotConnectSummary& out) const {
    const auto s = hot_connect_.status();
    out.set_state(std::string(hotconnect::to_string(s.state)));
    out.set_mode(std::string(hotconnect::to_string(s.options.mode)));
    out.set_border_close(s.options.border_close);
    std::uint32_t groups = 0;
    std::uint32_t present = 0;
    for (const auto& g : s.groups) {
        if (g.number == 0) continue;
        ++groups;
        if (g.status == hotconnect::GroupStatus::Present) ++present;
    }
    out.set_groups(groups);
    out.set_groups_present(present);
    if (s.last_result) out.set_last_result(std::string(hotconnect::to_string(*s.last_result)));
    out.set_changes(s.changes);
    out.set_slaves_on_bus(s.slaves_on_bus);
    out.set_mismatches(static_cast<std::uint32_t>(s.mismatches.size()));
}

control::HotConnectGroupsReply HotConnectService::groups() const {
    control::HotConnectGroupsReply reply;
    fill_summary(*reply.mutable_summary());
    const auto s = hot_connect_.status();
    for (const auto& g : s.groups) {
        auto* out = reply.add_groups();
        out->set_number(static_cast<std::uint32_t>(g.number));
        out->set_name(g.name);
        out->set_floating(g.floating);
        out->set_identification(identification_text(g.identification));
        out->set_status(std::string(hotconnect::to_string(g.status)));
        for (const auto& m : g.members) {
            auto* member = out->add_members();
            member->set_slave(static_cast<std::uint32_t>(m.slave));
            member->set_name(m.name);
            member->set_station(m.station);
            member->set_present(m.present);
            member->set_al_state(m.al_status == 0 ? std::string("?") : wire::AlStatus{m.al_status}.to_string());
        }
    }
    for (const auto& m : s.mismatches) {
        auto* out = reply.add_mismatches();
        out->set_position(m.position);
        out->set_kind(std::string(bus::to_string(m.match)));
        if (m.previous_station) out->set_previous_station(*m.previous_station);
        if (m.previous_port) out->set_previous_port(std::string(1, *m.previous_port));
        if (m.previous_position) out->set_previous_position(*m.previous_position);
        if (m.found) {
            out->set_found_vendor(m.found->vendor_id);
            out->set_found_product(m.found->product_code);
            out->set_found_revision(m.found->revision_no);
            out->set_found_serial(m.found->serial_no);
        }
        out->set_found_station(m.found_station);
        if (m.identification) {
            out->set_identification_error(m.identification->read != m.identification->expected);
            out->set_identification_ado(m.identification->ado);
            if (m.identification->read) out->set_value_read(*m.identification->read);
            out->set_value_expected(m.identification->expected);
        }
        out->set_text(m.text);
    }
    for (const auto& port : s.blocked) set_port(*reply.add_blocked(), port);
    return reply;
}

control::Response HotConnectService::handle(const control::Request& request) {
    switch (request.kind_case()) {
        case control::Request::kHcGroups: {
            control::Response r = accepted();
            *r.mutable_hc_groups() = groups();
            return r;
        }
        case control::Request::kHcAccept: {
            const auto done = hot_connect_.accept();
            return done ? accepted() : refused(done.error());
        }
        case control::Request::kHcForce: {
            const auto done = hot_connect_.force_topology_change();
            return done ? accepted() : refused(done.error());
        }
        case control::Request::kHcBlockNode: {
            const auto& b = request.hc_block_node();
            const auto done = hot_connect_.block_node(
                b.has_mismatch() ? std::optional<std::size_t>(b.mismatch()) : std::nullopt,
                b.has_station() ? std::optional<std::uint16_t>(static_cast<std::uint16_t>(b.station())) : std::nullopt);
            if (!done) return refused(done.error());
            control::Response r = accepted();
            set_port(*r.mutable_hc_ports()->add_ports(), *done);
            return r;
        }
        case control::Request::kHcOpenBlockedPorts: {
            const auto done = hot_connect_.open_blocked_ports();
            if (!done) return refused(done.error());
            control::Response r = accepted();
            for (const auto& port : *done) set_port(*r.mutable_hc_ports()->add_ports(), port);
            return r;
        }
        case control::Request::kHcSetPort: {
            const auto& p = request.hc_set_port();
            const auto port = port_of(p.port());
            const auto setting = hotconnect::loop_setting_from(p.setting());
            if (!port) {
                return refused({hotconnect::OperationError::InvalidParam,
                                fmt::format("port: '{}' is not one of B, C, D", p.port())});
            }
            if (!setting) {
                return refused({hotconnect::OperationError::InvalidParam,
                                fmt::format("setting: '{}' is not one of auto, auto-close, open, closed", p.setting())});
            }
            if (p.station() > 0xFFFF) {
                return refused({hotconnect::OperationError::InvalidParam, fmt::format("station {} is out of range", p.station())});
            }
            const auto done = hot_connect_.set_port(static_cast<std::uint16_t>(p.station()), *port, *setting);
            return done ? accepted() : refused(done.error());
        }
        case control::Request::kHcSetAlias: {
            const auto& a = request.hc_set_alias();
            if (a.station() > 0xFFFF || a.alias() > 0xFFFF) {
                return refused({hotconnect::OperationError::InvalidParam, "station and alias must be 0..65535"});
            }
            const auto done = hot_connect_.set_alias(static_cast<std::uint16_t>(a.station()), static_cast<std::uint16_t>(a.alias()));
            if (!done) return refused(done.error());
            control::Response r = accepted();
            r.mutable_hc_alias()->set_previous(*done);
            return r;
        }
        default: break;
    }
    return refused({hotconnect::OperationError::InvalidParam, "not a Hot-Connect request"});
}

}  // namespace ecpair::daemon
