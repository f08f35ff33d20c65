#include "ecpair/hotconnect/group_bring_up.hpp"

#include <fmt/format.h>

#include "ecpair/common/bytes.hpp"
#include "ecpair/common/log.hpp"
#include "ecpair/master/master_events.hpp"
#include "ecpair/eni/identification.hpp"
#include "ecpair/dc/start_time.hpp"
#include "ecpair/sequencer/identification_update.hpp"
#include "ecpair/wire/al_status.hpp"
#include "ecpair/wire/esc_registers.hpp"
#include "hotconnect_log.hpp"

namespace ecpair::hotconnect {
namespace {

using sequencer::MasterState;

constexpr std::uint8_t kErrorAcknowledge = 0x10;
constexpr std::chrono::milliseconds kInitTimeout{2000};

std::string slave_label(const eni::Slave& s) { return fmt::format("slave '{}' (station {})", s.info.name, s.info.phys_addr); }

BringUpFailure failure_of(std::size_t slave, const sequencer::InitCmdError& e) {
    return BringUpFailure{slave, e.describe(), e.al_status_code};
}

// The master's BWR of a transition, sent to one slave instead of all.
eni::EcatCmd for_one_slave(const eni::EcatCmd& broadcast, const eni::Slave& slave) {
    eni::EcatCmd cmd = broadcast;
    cmd.command = wire::Command::Apwr;
    cmd.adp = slave.info.auto_inc_addr;
    cmd.expected_wkc = 1;
    cmd.validate.reset();
    return cmd;
}

}  // namespace

GroupBringUp::GroupBringUp(std::shared_ptr<const eni::EniConfig> eni, bus::BusAccess& bus, sequencer::Clock& clock,
                           std::function<void(master::EventKind, std::uint32_t, std::uint32_t)> raise)
    : eni_(std::move(eni)),
      bus_(bus),
      clock_(clock),
      raise_(std::move(raise)),
      init_cmds_(bus, clock),
      mailboxes_(*eni_, bus, clock),
      mailbox_init_cmds_(clock) {}

GroupBringUp::~GroupBringUp() = default;

sequencer::CommandContext GroupBringUp::context_for(const BringUpRequest& request, std::size_t index) const {
    const auto& slave = eni_->slaves[index];
    sequencer::CommandContext context;
    context.owner = slave.info.name;
    context.station = slave.info.phys_addr;
    context.slave_index = index;
    context.position_shift = request.position_shift[index];
    context.dc = dc::start_time_parameters(*eni_, index, request.present);
    return context;
}

// The state all the slaves are in (by their station address), nullopt when they
// differ, one lacks its address or one does not answer.
std::optional<MasterState> GroupBringUp::common_state(const BringUpRequest& request) {
    std::optional<MasterState> common;
    for (const auto index : request.slaves) {
        const auto& slave = eni_->slaves[index];
        const auto position = static_cast<std::uint16_t>(slave.info.ring_position - request.position_shift[index]);
        auto reply = bus::read_register(bus_, bus::SlaveAddress::position(position), wire::reg::kStationAddress, 2);
        if (!reply || reply->wkc != 1 || load_le<std::uint16_t>(reply->data, 0) != slave.info.phys_addr) return std::nullopt;
        auto status = bus::read_register(bus_, bus::SlaveAddress::station(slave.info.phys_addr), wire::reg::kAlStatus, 2);
        if (!status || status->wkc != 1) return std::nullopt;
        const auto state = sequencer::to_master_state(static_cast<eni::SlaveState>(wire::AlStatus{status->data[0]}.state()));
        if (!state || (common && *common != *state)) return std::nullopt;
        common = state;
    }
    return common;
}

BringUpResult GroupBringUp::run(const BringUpRequest& request, const std::function<void()>& reached_safeop,
                                std::stop_token stop) {
    BringUpResult result;
    const auto started = clock_.now();
    MasterState current = MasterState::Init;
    if (!request.reset_first) {
        if (const auto state = common_state(request)) current = *state;
    }
    result.reached = current;
    if (current == MasterState::Safeop || current == MasterState::Op) reached_safeop();
    while (static_cast<int>(current) < static_cast<int>(request.target)) {
        const auto t = *sequencer::next_transition(current, request.target, *eni_);
        if (auto failure = run_transition(request, t, stop)) {
            result.failure = std::move(failure);
            break;
        }
        current = *sequencer::transition_target(t);
        result.reached = current;
        if (t == eni::Transition::PS) {
            // Input-word identification can only be read now, with the inputs running.
            if (auto wrong = check_input_words(request)) {
                result.failure = std::move(wrong);
                break;
            }
            reached_safeop();
        }
    }
    const auto ms = std::chrono::duration_cast<std::chrono::milliseconds>(clock_.now() - started).count();
    if (result.failure) {
        log()->error("bring-up of {} slave(s) stopped in {} after {} ms: {}", request.slaves.size(),
                     sequencer::to_string(result.reached), ms, result.failure->message);
    } else {
        log()->info("{} slave(s) brought to {} in {} ms", request.slaves.size(), sequencer::to_string(result.reached), ms);
    }
    return result;
}

std::optional<BringUpFailure> GroupBringUp::check_input_words(const BringUpRequest& request) {
    for (const auto index : request.slaves) {
        const auto& slave = eni_->slaves[index];
        const auto spec = eni::identification_of(slave);
        if (spec.mode != eni::IdentificationMode::InputWord) continue;
        auto reply = bus::read_register(bus_, bus::SlaveAddress::station(slave.info.phys_addr), spec.ado, 2);
        std::optional<std::uint16_t> read;
        if (reply && reply->wkc == 1) read = load_le<std::uint16_t>(reply->data, 0);
        if (read == spec.value) {
            log()->info("{}: input word at 0x{:04x} identifies it ({})", slave_label(slave), spec.ado, spec.value);
            continue;
        }
        return BringUpFailure{index,
                              fmt::format("{}: wrong identification: input word at 0x{:04x} expected {}, read {}",
                                          slave_label(slave), spec.ado, spec.value,
                                          read ? fmt::format("{}", *read) : std::string("nothing readable")),
                              std::nullopt};
    }
    return std::nullopt;
}

std::optional<BringUpFailure> GroupBringUp::run_transition(const BringUpRequest& request, eni::Transition t,
                                                           std::stop_token stop) {
    std::vector<bool> only(eni_->slaves.size(), false);
    for (const auto index : request.slaves) only[index] = true;
    const auto plan = sequencer::plan_transition(*eni_, t, only);
    // The master's broadcast writes of this transition, for each new slave.
    for (const auto& cmd : plan.master_before) {
        if (cmd.command != wire::Command::Bwr) continue;
        for (const auto index : request.slaves) {
            const auto one = for_one_slave(cmd, eni_->slaves[index]);
            if (auto r = init_cmds_.run(one, context_for(request, index), stop); !r) return failure_of(index, r.error());
        }
    }
    for (const auto& slave : plan.slaves) {
        if (auto failure = run_slave(request, slave, t, stop, true)) return failure;
    }
    for (const auto& cmd : plan.master_after) {
        if (cmd.command != wire::Command::Bwr) continue;
        for (const auto index : request.slaves) {
            const auto one = for_one_slave(cmd, eni_->slaves[index]);
            if (auto r = init_cmds_.run(one, context_for(request, index), stop); !r) return failure_of(index, r.error());
        }
    }
    return std::nullopt;
}

std::optional<BringUpFailure> GroupBringUp::run_slave(const BringUpRequest& request, const sequencer::SlavePlan& plan,
                                                      eni::Transition t, std::stop_token stop, bool may_recover) {
    const auto& slave = eni_->slaves[plan.slave_index];
    const auto context = context_for(request, plan.slave_index);
    // A slave left in ERROR (by an earlier attempt) is acknowledged first.
    const auto address =
        t == eni::Transition::IP
            ? bus::SlaveAddress::position(static_cast<std::uint16_t>(slave.info.ring_position - context.position_shift))
            : bus::SlaveAddress::station(slave.info.phys_addr);
    if (auto status = bus::read_register(bus_, address, wire::reg::kAlStatus, 2);
        status && status->wkc == 1 && wire::AlStatus{status->data[0]}.error()) {
        (void)bus::write_register(bus_, address, wire::reg::kAlControl,
                                  {static_cast<std::uint8_t>(wire::AlStatus{status->data[0]}.state() | kErrorAcknowledge), 0});
    }
    for (const auto& step : plan.steps) {
        if (const auto* cmd = std::get_if<eni::EcatCmd>(&step)) {
            if (auto r = init_cmds_.run(*cmd, context, stop); !r) {
                if (may_recover && t == eni::Transition::PS && sequencer::is_identification_update(r.error())) {
                    return recover(request, plan, t, stop);
                }
                return failure_of(plan.slave_index, r.error());
            }
            continue;
        }
        if (auto r = mailbox_init_cmds_.run(mailboxes_.find(plan.slave_index), step, context.describe(), stop); !r) {
            return BringUpFailure{plan.slave_index, r.error().describe(), std::nullopt};
        }
    }
    return std::nullopt;
}

std::optional<BringUpFailure> GroupBringUp::recover(const BringUpRequest& request, const sequencer::SlavePlan& plan,
                                                    eni::Transition t, std::stop_token stop) {
    const auto& slave = eni_->slaves[plan.slave_index];
    log()->warn("{}: AL status code 0x0061 (device identification value updated, ETG.1020): taking it through INIT",
                slave_label(slave));
    const auto alias = sequencer::reinitialise_after_identification_update(
        bus_, clock_, bus::SlaveAddress::station(slave.info.phys_addr), kInitTimeout, stop);
    if (!alias) return BringUpFailure{plan.slave_index, "recovering from 0x0061: " + alias.error(), sequencer::kIdentificationUpdated};
    if (raise_) {
        raise_(master::events::kSlaveIdentificationUpdated, static_cast<std::uint32_t>(plan.slave_index), *alias);
    }
    const auto& id = slave.info.identification;
    if (id && id->enabled && id->ado == eni::kStationAliasRegister && id->value && *id->value != 0 && *id->value != *alias) {
        return BringUpFailure{plan.slave_index,
                              fmt::format("{} now identifies as station alias {}, the ENI expects {}", slave_label(slave),
                                          *alias, *id->value),
                              sequencer::kIdentificationUpdated};
    }
    std::vector<bool> only(eni_->slaves.size(), false);
    only[plan.slave_index] = true;
    for (const auto& again : sequencer::plan_transition(*eni_, eni::Transition::IP, only).slaves) {
        if (auto f = run_slave(request, again, eni::Transition::IP, stop, false)) return f;
    }
    return run_slave(request, plan, t, stop, false);
}

}  // namespace ecpair::hotconnect
