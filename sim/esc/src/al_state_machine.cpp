// The transition functions are pure; AlStateMachine is the register side.
// The switch in al_control_transition() is SOES's ESC_state table with one
// deliberate difference: an invalid request out of BOOT keeps BOOT (with the
// error flag) instead of reporting PREOP, which the slave never was in.

#include "al_state_machine.hpp"

#include <fmt/format.h>

#include "ecpair/wire/al_status.hpp"
#include "ecpair/wire/esc_registers.hpp"
#include "register_map.hpp"

namespace ecpair::sim {
namespace {

namespace reg = wire::reg;

// AL control: b4 error acknowledge, b5 device identification request.
constexpr std::uint16_t kControlErrorAck = 0x0010;
constexpr std::uint16_t kControlIdRequest = 0x0020;

bool known_state(std::uint8_t value) {
    return value == 1 || value == 2 || value == 3 || value == 4 || value == 8;
}

std::string describe(const AlOutcome& outcome) {
    std::string text(to_string(outcome.status.state));
    if (outcome.status.error) text += "+ERR";
    if (outcome.status.id_loaded) text += "+ID";
    if (outcome.status_code != 0) {
        text += outcome.status.id_loaded
                    ? fmt::format(" (device ID 0x{:04x})", outcome.status_code)
                    : fmt::format(" (0x{:04x} {})", outcome.status_code, wire::al_status_code_text(outcome.status_code));
    }
    return text;
}

}  // namespace

std::string_view to_string(AlState state) {
    switch (state) {
        case AlState::Init: return "INIT";
        case AlState::Preop: return "PREOP";
        case AlState::Boot: return "BOOT";
        case AlState::Safeop: return "SAFEOP";
        case AlState::Op: return "OP";
    }
    return "?";
}

std::uint16_t AlStatusWord::encode() const {
    return static_cast<std::uint16_t>(static_cast<std::uint16_t>(state) | (error ? wire::AlStatus::kErrorBit : 0) |
                                      (id_loaded ? wire::AlStatus::kIdLoadedBit : 0));
}

AlControlWord AlControlWord::decode(std::uint16_t value) {
    return AlControlWord{static_cast<std::uint8_t>(value & 0x0F), (value & kControlErrorAck) != 0,
                         (value & kControlIdRequest) != 0};
}

std::optional<AlOutcome> al_control_transition(const AlOutcome& current, AlControlWord request, const AlChecks& checks) {
    const AlState from = current.status.state;
    const bool error_cleared = request.error_ack || request.requested == static_cast<std::uint8_t>(AlState::Init);
    if (current.status.error && !error_cleared) return std::nullopt;

    AlOutcome next;
    next.status.state = from;
    const auto reject = [&](AlState stay, std::uint16_t code) {
        next.status.state = stay;
        next.status.error = true;
        next.status_code = code;
    };
    const auto enter_if = [&](AlState target, AlState on_error, std::uint16_t code) {
        if (code != 0) {
            reject(on_error, code);
        } else {
            next.status.state = target;
        }
    };

    if (!known_state(request.requested)) {
        reject(from == AlState::Op ? AlState::Safeop : from, al_code::kUnknownState);
    } else {
        switch (static_cast<AlState>(request.requested)) {
            case AlState::Init: next.status.state = AlState::Init; break;
            case AlState::Preop:
                if (from == AlState::Init) {
                    const std::uint16_t refused = checks.entry_refusal(AlState::Preop);
                    enter_if(AlState::Preop, AlState::Init, refused != 0 ? refused : checks.mailbox_error(false));
                } else if (from == AlState::Boot) {
                    reject(AlState::Boot, al_code::kInvalidStateChange);
                } else {
                    next.status.state = AlState::Preop;
                }
                break;
            case AlState::Boot:
                if (from == AlState::Init || from == AlState::Boot) {
                    if (!checks.bootstrap_supported()) {
                        reject(AlState::Init, al_code::kBootstrapNotSupported);
                    } else {
                        enter_if(AlState::Boot, AlState::Init, checks.mailbox_error(true));
                    }
                } else {
                    reject(from == AlState::Op ? AlState::Safeop : from, al_code::kInvalidStateChange);
                }
                break;
            case AlState::Safeop:
                if (from == AlState::Preop || from == AlState::Safeop) {
                    const std::uint16_t refused = from == AlState::Preop ? checks.entry_refusal(AlState::Safeop) : 0;
                    enter_if(AlState::Safeop, AlState::Preop, refused != 0 ? refused : checks.process_data_error());
                } else if (from == AlState::Op) {
                    next.status.state = AlState::Safeop;
                } else {
                    reject(from, al_code::kInvalidStateChange);
                }
                break;
            case AlState::Op:
                if (from == AlState::Safeop) {
                    enter_if(AlState::Op, AlState::Safeop, checks.entry_refusal(AlState::Op));
                } else if (from == AlState::Op) {
                    next.status.state = AlState::Op;
                } else {
                    reject(from, al_code::kInvalidStateChange);
                }
                break;
        }
    }

    // Explicit device identification (SOES ESC_check_id_request / ESC_load_device_id).
    const bool request_allows_id =
        request.requested != static_cast<std::uint8_t>(AlState::Boot) &&
        (request.requested < static_cast<std::uint8_t>(AlState::Safeop) ||
         (!next.status.error && (next.status.state == AlState::Safeop || next.status.state == AlState::Op)));
    if (request.id_request && request_allows_id && next.status_code == al_code::kNone) {
        const std::uint16_t id = checks.device_id();
        if (id != 0) {
            next.status_code = id;
            next.status.id_loaded = true;
        }
    }
    return next;
}

std::optional<AlOutcome> al_sm_change_transition(const AlOutcome& current, AlControlWord last_request,
                                                 const AlChecks& checks) {
    const AlState state = current.status.state;
    if (state != AlState::Preop && state != AlState::Safeop && state != AlState::Op) return std::nullopt;
    const bool error_cleared = last_request.error_ack || last_request.requested == static_cast<std::uint8_t>(AlState::Init);
    if (current.status.error && !error_cleared) return std::nullopt;

    AlOutcome next;
    next.status.error = true;
    if (checks.has_mailbox()) {
        if (const std::uint16_t code = checks.mailbox_error(false); code != 0) {
            next.status.state = AlState::Init;
            next.status_code = code;
            return next;
        }
    }
    if (state == AlState::Safeop || state == AlState::Op) {
        if (const std::uint16_t code = checks.process_data_error(); code != 0) {
            next.status.state = AlState::Preop;
            next.status_code = code;
            return next;
        }
    }
    return std::nullopt;
}

std::optional<AlOutcome> al_local_error_transition(const AlOutcome& current, AlState fall_to, std::uint16_t code) {
    if (static_cast<std::uint8_t>(current.status.state) <= static_cast<std::uint8_t>(fall_to) ||
        current.status.state == AlState::Boot) {
        return std::nullopt;
    }
    AlOutcome next;
    next.status.state = fall_to;
    next.status.error = true;
    next.status_code = code;
    return next;
}

AlOutcome al_device_emulation_transition(AlControlWord request) {
    AlOutcome next;
    next.status.state = static_cast<AlState>(request.requested);
    return next;
}

AlStateMachine::AlStateMachine(EscMemory& memory, std::shared_ptr<spdlog::logger> log, std::string owner)
    : memory_(memory), log_(std::move(log)), owner_(std::move(owner)) {}

void AlStateMachine::reset() {
    current_ = AlOutcome{};
    last_request_ = AlControlWord{};
    memory_.store<std::uint16_t>(reg::kAlStatus, current_.status.encode());
    memory_.store<std::uint16_t>(reg::kAlStatusCode, current_.status_code);
}

bool AlStateMachine::on_control_written(const AlChecks& checks) {
    last_request_ = AlControlWord::decode(memory_.load<std::uint16_t>(reg::kAlControl));
    return apply(al_control_transition(current_, last_request_, checks), "AL control");
}

bool AlStateMachine::on_sm_activation_changed(const AlChecks& checks) {
    return apply(al_sm_change_transition(current_, last_request_, checks), "SyncManager change");
}

bool AlStateMachine::on_local_error(AlState fall_to, std::uint16_t code, std::string_view cause) {
    return apply(al_local_error_transition(current_, fall_to, code), cause);
}

bool AlStateMachine::on_control_written_device_emulation() {
    last_request_ = AlControlWord::decode(memory_.load<std::uint16_t>(reg::kAlControl));
    return apply(al_device_emulation_transition(last_request_), "AL control, device emulation");
}

bool AlStateMachine::apply(const std::optional<AlOutcome>& outcome, std::string_view cause) {
    if (!outcome) return false;
    const AlOutcome previous = current_;
    current_ = *outcome;
    const std::uint16_t status = current_.status.encode();
    if (status != previous.status.encode()) {
        memory_.store<std::uint16_t>(reg::kAlStatus, status);
        const auto request = memory_.load<std::uint16_t>(reg::kEcatEventRequest);
        memory_.store<std::uint16_t>(reg::kEcatEventRequest, static_cast<std::uint16_t>(request | regs::kEventAlStatus));
    }
    memory_.store<std::uint16_t>(reg::kAlStatusCode, current_.status_code);
    if (!(current_.status == previous.status) || current_.status_code != previous.status_code) {
        log_->info("{}: AL {} -> {} ({})", owner_, describe(previous), describe(current_), cause);
    }
    return current_.status.state != previous.status.state;
}

}  // namespace ecpair::sim
