#pragma once
// Executes one register InitCmd (eni::EcatCmd) the way ETG.2100 describes
// it, over bus::BusAccess:
//   - the address as written (APxx: Adp is the AutoIncAddr, moved up by the
//     absent optional slaves ahead; FPxx: PhysAddr; Bxx; Lxx: logical);
//   - Data, or DataLength zeros;
//   - Cnt: the expected WKC (absent: not checked);
//   - Retries: further attempts after a timeout or a WKC mismatch, each with
//     Timeout (ms; 100 ms when absent);
//   - Validate: read again with the same command until
//     (read & DataMask) == (Data & DataMask) or the Validate timeout passes,
//     one read per poll interval;
//   - the DC start time: an APWR/FPWR of zeros to 0x0990 carries the computed
//     start time instead (dc/start_time.hpp).
// A failure is an InitCmdError naming the owner, the ENI line and comment,
// the reason, and the slave's AL status and code when the command touches
// AL control or AL status.

#include <chrono>
#include <cstdint>
#include <optional>
#include <stop_token>
#include <string>

#include "ecpair/bus/bus_access.hpp"
#include "ecpair/common/expected.hpp"
#include "ecpair/eni/model.hpp"
#include "ecpair/sequencer/clock.hpp"
#include "ecpair/dc/start_time.hpp"
#include "ecpair/wire/al_status.hpp"

namespace ecpair::sequencer {

// Who a command belongs to: addressing adjustments and the words for errors.
struct CommandContext {
    std::string owner = "master";            // "master" or the slave's name
    std::optional<std::uint16_t> station;    // the slave's PhysAddr
    std::optional<std::size_t> slave_index;  // index into EniConfig::slaves
    // Absent optional slaves ahead of this one in ring order: its APxx
    // commands go that many positions nearer than the ENI wrote.
    std::uint16_t position_shift = 0;
    std::optional<dc::StartTimeParameters> dc;

    // "master", or "slave 'EL1008' (station 1001)".
    std::string describe() const;
};

enum class InitCmdFailure : std::uint8_t {
    Timeout,         // no reply in any attempt
    WkcMismatch,     // replies came back with the wrong WKC in every attempt
    ValidateFailed,  // the value read never matched before the Validate timeout
    DcStartTime,     // the reference clock's system time could not be read
    Bus,             // the bus refused (master INACTIVE, cancelled, request invalid)
    Stopped,         // the sequencer is shutting down
};

std::string_view to_string(InitCmdFailure failure);

struct InitCmdError {
    InitCmdFailure failure = InitCmdFailure::Timeout;
    std::optional<bus::BusErrc> bus_error;  // with Bus: what the bus said
    std::string owner;                      // CommandContext::describe()
    std::optional<std::size_t> slave_index;
    int eni_line = 0;
    std::string comment;
    std::string reason;  // "WKC expected 1, received 0 after 4 attempt(s)"
    std::optional<wire::AlStatus> al_status;
    std::optional<std::uint16_t> al_status_code;

    // "slave 'X' (station 1001), ENI line 123 'set device state to PREOP':
    //  validate: expected 02 mask 1f, last read 12; AL status PREOP+ERR, code 0x001d (invalid output configuration)"
    std::string describe() const;
};

struct InitCmdOptions {
    std::chrono::milliseconds default_timeout{100};  // per attempt, when the InitCmd has no Timeout
    std::chrono::nanoseconds start_time_margin = dc::kStartMargin;
};

class InitCmdRunner {
public:
    InitCmdRunner(bus::BusAccess& bus, Clock& clock, InitCmdOptions options = {});

    Expected<void, InitCmdError> run(const eni::EcatCmd& cmd, const CommandContext& context,
                                     std::stop_token stop = {});

private:
    Expected<bus::DatagramRequest, InitCmdError> build_request(const eni::EcatCmd& cmd, const CommandContext& context,
                                                               std::stop_token stop);
    Expected<bus::DatagramReply, InitCmdError> execute(const eni::EcatCmd& cmd, const CommandContext& context,
                                                       const bus::DatagramRequest& request, std::stop_token stop);
    Expected<void, InitCmdError> validate(const eni::EcatCmd& cmd, const CommandContext& context,
                                          const bus::DatagramRequest& request, bus::DatagramReply reply,
                                          std::stop_token stop);
    InitCmdError failure(const eni::EcatCmd& cmd, const CommandContext& context, InitCmdFailure kind,
                         std::string reason, const bus::DatagramRequest* request);

    bus::BusAccess& bus_;
    Clock& clock_;
    InitCmdOptions options_;
};

// The address of a command as it goes on the wire (APxx moved by the context's position shift).
std::uint32_t wire_address(const eni::EcatCmd& cmd, const CommandContext& context);

// Whether a command writes AL control (0x0120), and the state it requests then.
std::optional<std::uint8_t> requested_al_state(const eni::EcatCmd& cmd);

}  // namespace ecpair::sequencer
