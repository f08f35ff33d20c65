#pragma once
// The CoE server of an emulated slave: the MailboxHandler that answers SDO
// requests from its ObjectDictionary, the way a slave stack such as SOES
// does (ETG.1000.6 §5.6.2, details in docs/ESC_EMULATION.md "CoE server").
//
// Per request (the whole SM0 buffer, coded with wire/mailbox.hpp and
// wire/coe.hpp):
//
//  - mailbox header: a request repeating the previous non-zero counter is a
//    retransmission: it is not executed again, the last reply is posted
//    again. A header that is not acceptable gets a mailbox error reply
//    (type 0): length 0 or type 0 -> 0x0005 invalid header, length past the
//    mailbox -> 0x0008 invalid size, another protocol than CoE -> 0x0002;
//    a CoE part too short for its service -> 0x0006; a CoE service other
//    than SDO request and SDO Information -> 0x0004 (service 0 -> 0x0005);
//  - SDO: download and upload, expedited, normal and segmented, with
//    CompleteAccess from subindex 0 or 1; everything refused gets an SDO
//    abort (sent, like SOES, with CoE service "SDO request");
//  - SDO Information (CoE service 8): OD list, object and entry
//    descriptions from the same dictionary; a response longer than SM1 goes
//    out in fragments, the next one as soon as the master read SM1.
//
// Replies carry the slave's station address and a counter 1..7 of their
// own, and are never longer than SM1. A reply that finds SM1 still full
// waits there until the master has read SM1.

#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "ecpair/common/bytes.hpp"
#include "ecpair/eni/model.hpp"
#include "ecpair/sim/mailbox.hpp"
#include "ecpair/sim/object_dictionary.hpp"
#include "ecpair/wire/mailbox.hpp"

namespace ecpair::sim {

class SdoServer;
class SdoInformationServer;

// What the CoE server needs to know of, and tells, the slave it runs in.
class CoeSlaveContext {
public:
    // The source address of every reply (register 0x0010).
    virtual std::uint16_t station_address() const = 0;
    // PDO mapping and assignment are writable in PREOP only.
    virtual eni::SlaveState al_state() const = 0;
    // The master changed the PDOs of SyncManager `sm`: the number of bytes
    // they now map (nullopt: an assigned PDO is unknown), for the SM length
    // the slave expects before SAFEOP.
    virtual void process_data_size_changed(std::uint8_t sm, std::optional<std::uint16_t> bytes) = 0;

protected:
    ~CoeSlaveContext() = default;
};

class CoeServer final : public MailboxHandler {
public:
    // `mailbox_in_size`: the length of SM1, the most a reply may take.
    CoeServer(ObjectDictionary dictionary, CoeSlaveContext& slave, std::size_t mailbox_in_size);
    ~CoeServer() override;
    CoeServer(const CoeServer&) = delete;
    CoeServer& operator=(const CoeServer&) = delete;

    void on_request(ConstBytes request, MailboxOutbox& outbox) override;
    void on_reply_read(MailboxOutbox& outbox) override;
    void on_stopped() override;

private:
    void handle_coe(ConstBytes body, MailboxOutbox& outbox);
    void send_information_fragment(MailboxOutbox& outbox);
    void reply_error(std::uint16_t detail, MailboxOutbox& outbox);
    // Header + `payload_size` bytes already in reply_; posts it or keeps it waiting.
    void send(wire::MailboxType type, std::size_t payload_size, MailboxOutbox& outbox);
    void post_reply(MailboxOutbox& outbox);

    ObjectDictionary dictionary_;
    CoeSlaveContext& slave_;
    std::unique_ptr<SdoServer> sdo_;
    std::unique_ptr<SdoInformationServer> information_;
    std::vector<std::uint8_t> reply_;  // SM1-sized; the last reply, kept for a retransmitted request
    std::size_t reply_size_ = 0;       // 0: no reply yet
    bool reply_waiting_ = false;       // built while SM1 was full
    std::uint8_t last_request_counter_ = 0;
    std::uint8_t reply_counter_ = 0;
};

}  // namespace ecpair::sim
