#pragma once
// Runs a slave's mailbox InitCmds (the mailbox steps of a TransitionPlan:
// CoE, SoE and EoE) through its SlaveMailbox, one session per command, so
// that others who talk to the mailbox (the mailbox service) get their turn
// between two commands:
//   CoE: CoeInitCmdRunner (download, or upload);
//   SoE: OpCode 3 writes Data to the IDN's elements, OpCode 1 reads them
//        (the value is logged);
//   EoE: a set-IP-parameter request with Data. EC-Engineer writes Data with
//        the 4-byte EoE header in front (62 bytes), Elmo's EAS without it
//        (58): a Data of the header's size plus the IP parameters whose
//        first byte is a set-IP request is taken as the former.
// Timeout 0 (or none) means kDefaultTimeout. Disabled commands never reach
// here (the plan leaves them out). A failure names the slave, the ENI line
// and comment, and what the slave said.

#include <chrono>
#include <optional>
#include <stop_token>
#include <string>

#include "ecpair/bus/bus_access.hpp"
#include "ecpair/common/expected.hpp"
#include "ecpair/sequencer/clock.hpp"
#include "ecpair/sequencer/coe_init_cmd_runner.hpp"
#include "ecpair/sequencer/slave_mailboxes.hpp"
#include "ecpair/sequencer/transition_plan.hpp"

namespace ecpair::sequencer {

struct MailboxInitCmdError {
    std::string owner;  // "slave 'X' (station 1001)"
    int eni_line = 0;
    std::string comment;
    std::string reason;                    // what went wrong, with the request it happened in
    std::optional<bus::BusErrc> bus_error;  // the bus refused (master INACTIVE, cancelled)
    bool stopped = false;                   // the caller is shutting down

    std::string describe() const;
};

class MailboxInitCmdRunner {
public:
    static constexpr std::chrono::milliseconds kDefaultTimeout{3000};

    explicit MailboxInitCmdRunner(Clock& clock) : clock_(clock) {}

    // `step` is one of the mailbox kinds of SlaveStep; `mailbox` null: the slave has none.
    Expected<void, MailboxInitCmdError> run(SlaveMailbox* mailbox, const SlaveStep& step, const std::string& owner,
                                            std::stop_token stop = {});

private:
    Expected<void, MailboxInitCmdError> run_coe(SlaveMailbox& mailbox, const eni::CoeInitCmd& cmd,
                                                const std::string& owner, std::stop_token stop);
    Expected<void, MailboxInitCmdError> run_soe(SlaveMailbox& mailbox, const eni::SoeInitCmd& cmd,
                                                const std::string& owner, std::stop_token stop);
    Expected<void, MailboxInitCmdError> run_eoe(SlaveMailbox& mailbox, const eni::EoeInitCmd& cmd,
                                                const std::string& owner, std::stop_token stop);

    Clock& clock_;
    CoeInitCmdRunner coe_;
};

}  // namespace ecpair::sequencer
