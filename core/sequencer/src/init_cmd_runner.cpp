// One InitCmd: build the datagram (address with the position shift, data,
// the DC start time in place of zeros), send it up to 1 + Retries times
// until a reply with the expected WKC comes back, then poll with the same
// datagram while a Validate is not satisfied. The bus's own retries are
// switched off: the ENI's Retries count every attempt here.

#include "ecpair/sequencer/init_cmd_runner.hpp"

#include <algorithm>

#include <fmt/format.h>

#include "ecpair/common/bytes.hpp"
#include "ecpair/common/hex.hpp"
#include "ecpair/common/log.hpp"
#include "ecpair/wire/datagram.hpp"
#include "ecpair/wire/esc_registers.hpp"

namespace ecpair::sequencer {
namespace {

constexpr std::size_t kAlStatusReadLength = 6;  // 0x0130 status, 0x0132 reserved, 0x0134 code

bool single_slave(wire::Command command) {
    const auto addressing = wire::addressing_of(command);
    return addressing == wire::Addressing::AutoIncrement || addressing == wire::Addressing::Configured;
}

bool overlaps(std::uint16_t ado, std::size_t length, std::uint16_t first, std::size_t size) {
    return ado < first + size && first < ado + length;
}

// AL control 0x0120-0x0121 or AL status 0x0130-0x0135.
bool touches_al_registers(const eni::EcatCmd& cmd) {
    return single_slave(cmd.command) && (overlaps(cmd.ado, cmd.data.size(), wire::reg::kAlControl, 2) ||
                                         overlaps(cmd.ado, cmd.data.size(), wire::reg::kAlStatus, 6));
}

bool masked_equal(ConstBytes read, ConstBytes expected, ConstBytes mask) {
    if (read.size() < expected.size()) return false;
    for (std::size_t i = 0; i < expected.size(); ++i) {
        const std::uint8_t m = i < mask.size() ? mask[i] : 0xFF;
        if ((read[i] & m) != (expected[i] & m)) return false;
    }
    return true;
}

std::string hex(ConstBytes bytes) { return bytes.empty() ? std::string("(nothing)") : to_hex(bytes, " "); }

std::chrono::milliseconds attempt_timeout(const eni::EcatCmd& cmd, const InitCmdOptions& options) {
    return cmd.timeout && cmd.timeout->count() > 0 ? *cmd.timeout : options.default_timeout;
}

}  // namespace

std::string CommandContext::describe() const {
    if (!station) return owner;
    return fmt::format("slave '{}' (station {})", owner, *station);
}

std::string_view to_string(InitCmdFailure failure) {
    switch (failure) {
        case InitCmdFailure::Timeout: return "timeout";
        case InitCmdFailure::WkcMismatch: return "WKC mismatch";
        case InitCmdFailure::ValidateFailed: return "validate failed";
        case InitCmdFailure::DcStartTime: return "DC start time";
        case InitCmdFailure::Bus: return "bus refused";
        case InitCmdFailure::Stopped: return "stopped";
    }
    return "?";
}

std::string InitCmdError::describe() const {
    std::string text = fmt::format("{}, ENI line {}", owner, eni_line);
    if (!comment.empty()) text += fmt::format(" '{}'", comment);
    text += ": " + reason;
    if (al_status) {
        text += fmt::format("; AL status {}", al_status->to_string());
        if (al_status_code) {
            text += fmt::format(", code 0x{:04x} ({})", *al_status_code, wire::al_status_code_text(*al_status_code));
        }
    }
    return text;
}

std::uint32_t wire_address(const eni::EcatCmd& cmd, const CommandContext& context) {
    switch (wire::addressing_of(cmd.command)) {
        case wire::Addressing::Logical: return cmd.logical_address;
        case wire::Addressing::AutoIncrement:
            return wire::DatagramHeader::physical(static_cast<std::uint16_t>(cmd.adp + context.position_shift),
                                                  cmd.ado);
        default: return wire::DatagramHeader::physical(cmd.adp, cmd.ado);
    }
}

std::optional<std::uint8_t> requested_al_state(const eni::EcatCmd& cmd) {
    const auto addressing = wire::addressing_of(cmd.command);
    if (!wire::command_writes(cmd.command) || addressing == wire::Addressing::Logical ||
        !overlaps(cmd.ado, cmd.data.size(), wire::reg::kAlControl, 1)) {
        return std::nullopt;
    }
    return static_cast<std::uint8_t>(cmd.data[wire::reg::kAlControl - cmd.ado] & wire::AlStatus::kStateMask);
}

InitCmdRunner::InitCmdRunner(bus::BusAccess& bus, Clock& clock, InitCmdOptions options)
    : bus_(bus), clock_(clock), options_(options) {}

Expected<void, InitCmdError> InitCmdRunner::run(const eni::EcatCmd& cmd, const CommandContext& context,
                                                std::stop_token stop) {
    auto request = build_request(cmd, context, stop);
    if (!request) return unexpected(std::move(request).error());
    auto reply = execute(cmd, context, *request, stop);
    if (!reply) return unexpected(std::move(reply).error());
    if (!cmd.validate) return {};
    return validate(cmd, context, *request, std::move(reply).value(), stop);
}

Expected<bus::DatagramRequest, InitCmdError> InitCmdRunner::build_request(const eni::EcatCmd& cmd,
                                                                          const CommandContext& context,
                                                                          std::stop_token stop) {
    bus::DatagramRequest request;
    request.command = cmd.command;
    request.address = wire_address(cmd, context);
    request.data = cmd.data;
    request.timeout = attempt_timeout(cmd, options_);
    request.retries = 0;
    if (!dc::is_zero_start_time_write(cmd)) return request;

    if (!context.dc) {
        logger("sequencer")->warn("{}: ENI line {}: DC start time written as zeros (no reference clock known)",
                                  context.describe(), cmd.source_line);
        return request;
    }
    bus::DatagramRequest read_time;
    read_time.command = context.dc->reference_clock.read_command();
    read_time.address = wire::DatagramHeader::physical(context.dc->reference_clock.adp(), wire::reg::kDcSystemTime);
    read_time.data.assign(8, 0);
    read_time.timeout = request.timeout;
    read_time.retries = cmd.retries;
    if (stop.stop_requested()) return unexpected(failure(cmd, context, InitCmdFailure::Stopped, "stopped", nullptr));
    auto time = bus_.exchange(read_time);
    if (!time || time->wkc != 1 || time->data.size() < 8) {
        const auto why = time ? fmt::format("WKC {}", time->wkc) : time.error().message;
        return unexpected(failure(cmd, context, InitCmdFailure::DcStartTime,
                                  fmt::format("DC start time: system time of the reference clock at {} not readable ({})",
                                              context.dc->reference_clock.to_string(), why),
                                  nullptr));
    }
    const auto system_time = load_le<std::uint64_t>(time->data, 0);
    const auto start = dc::start_time(system_time, options_.start_time_margin, context.dc->cycle_time_ns,
                                     context.dc->shift_time_ns);
    for (std::size_t i = 0; i < request.data.size() && i < 8; ++i) {
        request.data[i] = static_cast<std::uint8_t>(start >> (8 * i));
    }
    logger("sequencer")->debug("{}: DC start time {} ns (system time {} ns, cycle {} ns, shift {} ns)",
                               context.describe(), start, system_time, context.dc->cycle_time_ns,
                               context.dc->shift_time_ns);
    return request;
}

Expected<bus::DatagramReply, InitCmdError> InitCmdRunner::execute(const eni::EcatCmd& cmd,
                                                                  const CommandContext& context,
                                                                  const bus::DatagramRequest& request,
                                                                  std::stop_token stop) {
    const std::uint32_t attempts = cmd.retries + 1;
    std::optional<std::uint16_t> wrong_wkc;
    for (std::uint32_t attempt = 1; attempt <= attempts; ++attempt) {
        if (stop.stop_requested()) return unexpected(failure(cmd, context, InitCmdFailure::Stopped, "stopped", nullptr));
        auto reply = bus_.exchange(request);
        if (!reply) {
            const auto code = reply.error().code;
            if (code == bus::BusErrc::Timeout || code == bus::BusErrc::LinkFailure) continue;
            auto error = failure(cmd, context, InitCmdFailure::Bus, reply.error().message, nullptr);
            error.bus_error = code;
            return unexpected(std::move(error));
        }
        if (cmd.expected_wkc && reply->wkc != *cmd.expected_wkc) {
            wrong_wkc = reply->wkc;
            continue;
        }
        return std::move(reply).value();
    }
    if (wrong_wkc) {
        return unexpected(failure(cmd, context, InitCmdFailure::WkcMismatch,
                                  fmt::format("WKC expected {}, received {} after {} attempt(s)", *cmd.expected_wkc,
                                              *wrong_wkc, attempts),
                                  &request));
    }
    return unexpected(failure(cmd, context, InitCmdFailure::Timeout,
                              fmt::format("no reply within {} ms in {} attempt(s)", request.timeout.count(), attempts),
                              &request));
}

Expected<void, InitCmdError> InitCmdRunner::validate(const eni::EcatCmd& cmd, const CommandContext& context,
                                                     const bus::DatagramRequest& request, bus::DatagramReply reply,
                                                     std::stop_token stop) {
    const auto& wanted = *cmd.validate;
    const auto timeout = wanted.timeout.count() > 0 ? wanted.timeout : request.timeout;
    const auto deadline = clock_.now() + timeout;
    std::vector<std::uint8_t> last_read = reply.data;
    for (;;) {
        if (masked_equal(last_read, wanted.data, wanted.mask)) return {};
        if (clock_.now() >= deadline) break;
        clock_.sleep_for(kPollInterval, stop);
        if (stop.stop_requested()) return unexpected(failure(cmd, context, InitCmdFailure::Stopped, "stopped", nullptr));
        auto again = bus_.exchange(request);
        if (!again) {
            const auto code = again.error().code;
            if (code == bus::BusErrc::Timeout || code == bus::BusErrc::LinkFailure) continue;
            auto error = failure(cmd, context, InitCmdFailure::Bus, again.error().message, nullptr);
            error.bus_error = code;
            return unexpected(std::move(error));
        }
        if (!cmd.expected_wkc || again->wkc == *cmd.expected_wkc) last_read = std::move(again->data);
    }
    const auto mask_text = wanted.mask.empty() ? std::string() : fmt::format(" mask {}", hex(wanted.mask));
    return unexpected(failure(cmd, context, InitCmdFailure::ValidateFailed,
                              fmt::format("validate: expected {}{}, last read {} (timeout {} ms)", hex(wanted.data),
                                          mask_text, hex(last_read), timeout.count()),
                              &request));
}

InitCmdError InitCmdRunner::failure(const eni::EcatCmd& cmd, const CommandContext& context, InitCmdFailure kind,
                                    std::string reason, const bus::DatagramRequest* request) {
    InitCmdError error;
    error.failure = kind;
    error.owner = context.describe();
    error.slave_index = context.slave_index;
    error.eni_line = cmd.source_line;
    error.comment = cmd.comment;
    error.reason = std::move(reason);
    if (request && touches_al_registers(cmd)) {
        // Read AL status and code the same way the command addressed the slave.
        bus::DatagramRequest read_status;
        read_status.command = wire::addressing_of(cmd.command) == wire::Addressing::AutoIncrement
                                  ? wire::Command::Aprd
                                  : wire::Command::Fprd;
        read_status.address = wire::DatagramHeader::physical(static_cast<std::uint16_t>(request->address & 0xFFFF),
                                                             wire::reg::kAlStatus);
        read_status.data.assign(kAlStatusReadLength, 0);
        read_status.timeout = request->timeout;
        read_status.retries = 1;
        if (auto status = bus_.exchange(read_status);
            status && status->wkc == 1 && status->data.size() >= kAlStatusReadLength) {
            error.al_status = wire::AlStatus{status->data[0]};
            error.al_status_code = load_le<std::uint16_t>(status->data, 4);
        }
    }
    return error;
}

}  // namespace ecpair::sequencer
