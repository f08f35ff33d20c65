// One mailbox InitCmd per call (see the header): open the slave's mailbox,
// run the protocol client, turn its error into a MailboxInitCmdError.

#include "ecpair/sequencer/mailbox_init_cmd_runner.hpp"

#include <fmt/format.h>

#include "ecpair/common/hex.hpp"
#include "ecpair/common/log.hpp"
#include "ecpair/sequencer/eoe_client.hpp"
#include "ecpair/sequencer/soe_client.hpp"
#include "ecpair/wire/eoe.hpp"

namespace ecpair::sequencer {
namespace {

constexpr std::uint8_t kSoeRead = 1;

template <class Cmd>
std::chrono::milliseconds timeout_of(const Cmd& cmd) {
    return cmd.timeout.count() > 0 ? cmd.timeout : MailboxInitCmdRunner::kDefaultTimeout;
}

template <class Cmd>
MailboxInitCmdError failure(const Cmd& cmd, const std::string& owner, const ProtocolError& error) {
    return MailboxInitCmdError{owner, cmd.source_line, cmd.comment, error.message, error.bus_error,
                               error.failure == ProtocolFailure::Stopped};
}

int line_of(const SlaveStep& step) {
    return std::visit([](const auto& cmd) { return cmd.source_line; }, step);
}

std::string_view protocol_of(const SlaveStep& step) {
    if (std::holds_alternative<eni::CoeInitCmd>(step)) return "CoE";
    if (std::holds_alternative<eni::SoeInitCmd>(step)) return "SoE";
    return "EoE";
}

}  // namespace

std::string MailboxInitCmdError::describe() const {
    std::string text = fmt::format("{}, ENI line {}", owner, eni_line);
    if (!comment.empty()) text += fmt::format(" '{}'", comment);
    return text + ": " + reason;
}

Expected<void, MailboxInitCmdError> MailboxInitCmdRunner::run(SlaveMailbox* mailbox, const SlaveStep& step,
                                                              const std::string& owner, std::stop_token stop) {
    if (mailbox == nullptr) {
        return unexpected(MailboxInitCmdError{owner, line_of(step), {},
                                              fmt::format("{} InitCmd but no mailbox configured", protocol_of(step)),
                                              std::nullopt, false});
    }
    if (const auto* coe = std::get_if<eni::CoeInitCmd>(&step)) return run_coe(*mailbox, *coe, owner, stop);
    if (const auto* soe = std::get_if<eni::SoeInitCmd>(&step)) return run_soe(*mailbox, *soe, owner, stop);
    if (const auto* eoe = std::get_if<eni::EoeInitCmd>(&step)) return run_eoe(*mailbox, *eoe, owner, stop);
    return unexpected(MailboxInitCmdError{owner, line_of(step), {}, "not a mailbox InitCmd", std::nullopt, false});
}

Expected<void, MailboxInitCmdError> MailboxInitCmdRunner::run_coe(SlaveMailbox& mailbox, const eni::CoeInitCmd& cmd,
                                                                  const std::string& owner, std::stop_token stop) {
    auto session = mailbox.open();
    SdoClient sdo(session.transport(), clock_);
    auto done = coe_.run(sdo, cmd, owner, stop);
    if (done) return {};
    const auto& e = done.error();
    return unexpected(MailboxInitCmdError{e.owner, e.eni_line, e.comment, e.sdo.message, e.sdo.bus_error,
                                          e.sdo.failure == SdoFailure::Stopped});
}

Expected<void, MailboxInitCmdError> MailboxInitCmdRunner::run_soe(SlaveMailbox& mailbox, const eni::SoeInitCmd& cmd,
                                                                  const std::string& owner, std::stop_token stop) {
    auto session = mailbox.open();
    SoeClient soe(session.transport(), clock_);
    if (cmd.opcode == kSoeRead) {
        auto value = soe.read(cmd.drive_no, cmd.idn, cmd.elements, timeout_of(cmd), stop);
        if (!value) return unexpected(failure(cmd, owner, value.error()));
        logger("sequencer")->debug("{}: ENI line {}: {} of drive {} = {}", owner, cmd.source_line,
                                   wire::idn_text(cmd.idn), cmd.drive_no, to_hex(*value, " "));
        return {};
    }
    if (auto written = soe.write(cmd.drive_no, cmd.idn, cmd.elements, cmd.data, timeout_of(cmd), stop); !written) {
        return unexpected(failure(cmd, owner, written.error()));
    }
    return {};
}

Expected<void, MailboxInitCmdError> MailboxInitCmdRunner::run_eoe(SlaveMailbox& mailbox, const eni::EoeInitCmd& cmd,
                                                                  const std::string& owner, std::stop_token stop) {
    ConstBytes data = cmd.data;
    std::uint8_t port = 0;
    if (data.size() >= wire::EoeHeader::kSize + wire::EoeIpParameters::kEncodedSize) {
        if (const auto header = wire::EoeHeader::decode(data); header && header->type == wire::EoeFrameType::SetIpRequest) {
            port = header->port;
            data = data.subspan(wire::EoeHeader::kSize);
        }
    }
    auto session = mailbox.open();
    EoeClient eoe(session.transport(), clock_);
    if (auto set = eoe.set_ip_parameters(data, port, timeout_of(cmd), stop); !set) {
        return unexpected(failure(cmd, owner, set.error()));
    }
    if (const auto parameters = wire::EoeIpParameters::decode(data)) {
        logger("sequencer")->info("{}: EoE IP parameters set: {}", owner, parameters->describe());
    }
    return {};
}

}  // namespace ecpair::sequencer
