#pragma once
// The EtherCAT state machine of the emulated slave stack (esc-facts.md §2
// "ESM"), following SOES ESC_state / ESC_sm_act_event.
//
// al_control_transition() is the whole rule for one write of AL control:
//
//  - an error acknowledge (b4) or a request for INIT clears the error flag;
//    otherwise, while the error flag is set, the request is ignored;
//  - I->P checks the mailbox SyncManagers (else INIT+ERR 0x0016), I->B the
//    bootstrap ones (0x0015; 0x0013 when the slave has no bootstrap mailbox),
//    P->S (and S->S) the process data SyncManagers (else PREOP+ERR,
//    0x001D outputs / 0x001E inputs); before those, the application may
//    refuse the state (entry_refusal: the ETG.1020 race, a slave told to
//    refuse): it stays in the state it was in, with ERR and that code;
//  - down to any lower state of INIT/PREOP/SAFEOP is allowed, BOOT only from
//    and to INIT, upward one step at a time; any other transition keeps the
//    state and sets ERR with 0x0011 (OP->BOOT falls back to SAFEOP);
//  - an undefined state value sets ERR with 0x0012 (OP falls back to SAFEOP);
//  - a successful transition clears the AL status code; then, with the device
//    identification request (b5), no status code pending, a request other
//    than BOOT and either a request below SAFEOP or a result of SAFEOP/OP, a
//    non-zero device ID goes into 0x0134 and the status gets b5.
//
// al_sm_change_transition() is the check SOES runs when the master changed a
// SyncManager's activation while the slave is in PREOP/SAFEOP/OP: a broken
// mailbox configuration drops it to INIT+ERR (0x0016), a broken process data
// configuration drops SAFEOP/OP to PREOP+ERR.
//
// al_local_error_transition() is the stack giving up a state on its own
// (the SyncManager watchdog expired in OP: SAFEOP+ERR 0x001B).
//
// al_device_emulation_transition() is the ESC without a stack (0x0141 b0):
// AL status takes the state AL control asks for, with no check, no error
// and no device ID.
//
// AlStateMachine applies the results to 0x0130/0x0134, raises the AL status
// event (0x0210 b3) and logs every change.

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>

#include <spdlog/logger.h>

#include "esc_memory.hpp"

namespace ecpair::sim {

enum class AlState : std::uint8_t { Init = 1, Preop = 2, Boot = 3, Safeop = 4, Op = 8 };
std::string_view to_string(AlState state);

namespace al_code {
inline constexpr std::uint16_t kNone = 0x0000;
inline constexpr std::uint16_t kInvalidStateChange = 0x0011;
inline constexpr std::uint16_t kUnknownState = 0x0012;
inline constexpr std::uint16_t kBootstrapNotSupported = 0x0013;
inline constexpr std::uint16_t kInvalidBootstrapMailbox = 0x0015;
inline constexpr std::uint16_t kInvalidMailbox = 0x0016;
inline constexpr std::uint16_t kInvalidOutputs = 0x001D;
inline constexpr std::uint16_t kInvalidInputs = 0x001E;
inline constexpr std::uint16_t kSmWatchdog = 0x001B;
}  // namespace al_code

struct AlStatusWord {
    AlState state = AlState::Init;
    bool error = false;
    bool id_loaded = false;

    std::uint16_t encode() const;
    friend bool operator==(const AlStatusWord&, const AlStatusWord&) = default;
};

struct AlControlWord {
    std::uint8_t requested = 1;  // raw 4-bit state request
    bool error_ack = false;
    bool id_request = false;

    static AlControlWord decode(std::uint16_t value);
};

// What the slave stack checks before entering a state. Each returns 0 when
// the configuration is right, else the AL status code to report.
class AlChecks {
public:
    virtual std::uint16_t mailbox_error(bool bootstrap) const = 0;
    virtual bool bootstrap_supported() const = 0;
    virtual bool has_mailbox() const = 0;
    virtual std::uint16_t process_data_error() const = 0;
    virtual std::uint16_t device_id() const = 0;
    // The application refuses to enter `target` (Preop/Safeop/Op): the AL
    // status code to report, 0 when it may.
    virtual std::uint16_t entry_refusal(AlState target) const = 0;

protected:
    ~AlChecks() = default;
};

struct AlOutcome {
    AlStatusWord status;
    std::uint16_t status_code = 0;
};

// nullopt: the request is ignored (an error is pending and not acknowledged).
std::optional<AlOutcome> al_control_transition(const AlOutcome& current, AlControlWord request, const AlChecks& checks);
// nullopt: nothing to do.
std::optional<AlOutcome> al_sm_change_transition(const AlOutcome& current, AlControlWord last_request,
                                                 const AlChecks& checks);
// nullopt: the slave is not in a state above `fall_to` (nothing to give up).
std::optional<AlOutcome> al_local_error_transition(const AlOutcome& current, AlState fall_to, std::uint16_t code);
AlOutcome al_device_emulation_transition(AlControlWord request);

class AlStateMachine {
public:
    AlStateMachine(EscMemory& memory, std::shared_ptr<spdlog::logger> log, std::string owner);

    // Power-on: INIT, no error, code 0.
    void reset();
    // The master wrote AL control (the frame ended). Returns true when the state changed.
    bool on_control_written(const AlChecks& checks);
    // The master changed a SyncManager activation. Returns true when the state changed.
    bool on_sm_activation_changed(const AlChecks& checks);
    // The stack leaves its state on its own (e.g. the SM watchdog). Returns true when the state changed.
    bool on_local_error(AlState fall_to, std::uint16_t code, std::string_view cause);
    // Device emulation: the master wrote AL control. Returns true when the state changed.
    bool on_control_written_device_emulation();

    AlState state() const { return current_.status.state; }

private:
    bool apply(const std::optional<AlOutcome>& outcome, std::string_view cause);

    EscMemory& memory_;
    std::shared_ptr<spdlog::logger> log_;
    std::string owner_;
    AlOutcome current_;
    AlControlWord last_request_;  // the ack logic of SyncManager checks uses it
};

}  // namespace ecpair::sim
