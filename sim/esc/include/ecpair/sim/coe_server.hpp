#pragma once
// The CoE server of an emulated slave: the MailboxProtocol that answers SDO
// requests from its ObjectDictionary, the way a slave stack such as SOES
// does (ETG.1000.6 §5.6.2, details in docs/ESC_EMULATION.md "CoE server").
// The MailboxServer around it does the mailbox header, the counter and SM1.
//
// Per request (the body after the mailbox header, coded with wire/coe.hpp):
//
//  - a CoE part too short for its service -> mailbox error 0x0006; a CoE
//    service other than SDO request and SDO Information -> 0x0004
//    (service 0 -> 0x0005);
//  - SDO: download and upload, expedited, normal and segmented, with
//    CompleteAccess from subindex 0 or 1; everything refused gets an SDO
//    abort (sent, like SOES, with CoE service "SDO request");
//  - SDO Information (CoE service 8): OD list, object and entry
//    descriptions from the same dictionary; a response longer than SM1 goes
//    out in fragments, the next one as soon as the master read SM1.
// Not offered in BOOT (the bootstrap mailbox is for FoE). Emergencies are
// built here (emergency()) and sent by the MailboxServer on request.

#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "ecpair/common/bytes.hpp"
#include "ecpair/eni/model.hpp"
#include "ecpair/sim/mailbox_server.hpp"
#include "ecpair/sim/object_dictionary.hpp"
#include "ecpair/wire/coe.hpp"

namespace ecpair::sim {

class SdoServer;
class SdoInformationServer;

// What the CoE server needs to know of, and tells, the slave it runs in.
class CoeSlaveContext : public MailboxSlave {
public:
    // The master changed the PDOs of SyncManager `sm`: the number of bytes
    // they now map (nullopt: an assigned PDO is unknown), for the SM length
    // the slave expects before SAFEOP. (PDO mapping and assignment are
    // writable in PREOP only: al_state().)
    virtual void process_data_size_changed(std::uint8_t sm, std::optional<std::uint16_t> bytes) = 0;

protected:
    ~CoeSlaveContext() = default;
};

class CoeServer final : public MailboxProtocol {
public:
    // `mailbox_in_size`: the length of SM1, the most a reply may take.
    CoeServer(ObjectDictionary dictionary, CoeSlaveContext& slave, std::size_t mailbox_in_size);
    ~CoeServer() override;
    CoeServer(const CoeServer&) = delete;
    CoeServer& operator=(const CoeServer&) = delete;

    wire::MailboxType type() const override { return wire::MailboxType::CoE; }
    bool serves_in(eni::SlaveState state) const override { return state != eni::SlaveState::Boot; }
    void on_request(ConstBytes body, MailboxReplies& replies) override;
    void on_reply_read(MailboxReplies& replies) override;
    void end_answer() override;
    void reset() override;

    // An emergency's body (CoE header, service 1, then the emergency) for MailboxServer::send_unsolicited.
    static std::vector<std::uint8_t> emergency(const wire::CoeEmergency& emergency);

private:
    void send_information_fragment(MailboxReplies& replies);

    ObjectDictionary dictionary_;
    CoeSlaveContext& slave_;
    std::unique_ptr<SdoServer> sdo_;
    std::unique_ptr<SdoInformationServer> information_;
    std::vector<std::uint8_t> reply_;  // SM1-sized: one reply body is built here
};

}  // namespace ecpair::sim
