#pragma once
// The mailbox services of one master, for the application and the operator
// (design.md §5): CoE SDO upload and download (expedited, normal, segmented,
// complete access), SDO Information (object list, object and entry
// descriptions, the whole dictionary), FoE read and write, SoE read and
// write, and beside them register read/write and SII read/write, which
// share their queue. Asynchronous: a request is queued per slave and
// carried out on a small pool of worker threads over the acyclic path
// (bus::BusAccess, the master's AcyclicQueue), and its completion is called
// once, with the typed value or a ServiceError; every kind comes as a
// completion-callback call and as a future.
//
// Order and parallelism: each slave's requests run one after the other in
// the order they were submitted; requests of different slaves run side by
// side (one per worker). A mailbox request holds its slave's mailbox for
// the whole transfer (SlaveMailbox::Session), between the state machine's
// mailbox InitCmds, never in the middle of one.
//
// Refusals at submit (the completion runs at once, on the caller's thread):
//   MasterRedStateInactive  the bus refuses: this member is INACTIVE (ask the ACTIVE);
//   InvalidParam            a position past the ENI's slaves, a bad length...;
//   SlaveNotPresent         the slave is not on the bus (Hot-Connect, startup scan);
//   NotSupported            no mailbox, or the ENI does not give the slave the protocol;
//   InvalidState            SII write while it is not allowed (options);
//   Busy                    max_queued requests are waiting already.
// A request admitted while this member was ACTIVE and cut by a role change
// (its transfer failed because the bus now refuses, or it was still
// queued) fails with Interrupted, which is retryable(): the caller sends it
// again to the new ACTIVE (design.md §4, REQ042).
//
// CoE emergencies (during a transfer, or found by the poll of idle
// mailboxes every emergency_poll) are raised as coe-emergency events (master::events::kCoeEmergency).
//
// Threads: every public function from any thread but the cycle thread's
// (submitting allocates); completions run on a worker (keep them short).
// The destructor fails what is still queued with Cancelled and waits for
// the running requests (they end at their next bus exchange).

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <functional>
#include <future>
#include <memory>
#include <mutex>
#include <optional>
#include <stop_token>
#include <string>
#include <string_view>
#include <thread>
#include <vector>

#include "ecpair/bus/bus_access.hpp"
#include "ecpair/common/expected.hpp"
#include "ecpair/eni/model.hpp"
#include "ecpair/master/event_queue.hpp"
#include "ecpair/master/master_events.hpp"
#include "ecpair/sequencer/clock.hpp"
#include "ecpair/sequencer/slave_mailboxes.hpp"
#include "ecpair/wire/coe.hpp"
#include "ecpair/wire/sdo_information.hpp"
#include "ecpair/wire/soe.hpp"

namespace ecpair::sequencer {

enum class ServiceErrc : std::uint8_t {
    MasterRedStateInactive,  // refused at once: this member is INACTIVE
    Interrupted,             // admitted, then cut by a role change: retry on the new ACTIVE
    InvalidParam,
    SlaveNotPresent,
    NotSupported,
    InvalidState,
    Timeout,
    SdoAbort,       // abort_code
    MailboxError,   // mailbox_error
    FoeError,       // foe_error
    SoeError,       // soe_error
    EoeError,       // eoe_result
    ProtocolError,  // an answer that is not one to the request
    NoResponse,     // register access: the slave did not answer (WKC 0)
    Busy,
    Cancelled,      // the service is shutting down
};

// "MasterRedStateInactive", "SdoAbort", ...
std::string_view to_string(ServiceErrc code);

struct ServiceError {
    ServiceErrc code = ServiceErrc::Cancelled;
    std::uint16_t position = 0;      // the slave, ENI order (0 = first)
    std::string slave;               // "slave 2 'Slave_1003 [Elmo Drive ]' (station 1003)"
    std::uint32_t abort_code = 0;    // SdoAbort
    std::uint16_t mailbox_error = 0; // MailboxError
    std::uint32_t foe_error = 0;     // FoeError
    std::uint16_t soe_error = 0;     // SoeError
    std::uint16_t eoe_result = 0;    // EoeError
    std::string message;             // "SdoAbort: slave 0 'X' (station 1001): SDO 0x6060:00 upload: aborted: 0x06020000 ..."

    bool retryable() const { return code == ServiceErrc::Interrupted; }
};

template <class T>
using ServiceResult = Expected<T, ServiceError>;
template <class T>
using Completion = std::function<void(ServiceResult<T>)>;

inline constexpr std::chrono::milliseconds kSdoTimeout{3000};
inline constexpr std::chrono::milliseconds kFoeTimeout{10000};
inline constexpr std::size_t kFoeMaxSize = 64u << 20;

// ---- requests (position: the slave's index in the ENI, 0 = first; timeout: for each answer of the slave)
struct SdoUpload {
    std::uint16_t position = 0;
    std::uint16_t index = 0;
    std::uint8_t subindex = 0;
    bool complete_access = false;
    std::chrono::milliseconds timeout = kSdoTimeout;
};
struct SdoDownload {
    std::uint16_t position = 0;
    std::uint16_t index = 0;
    std::uint8_t subindex = 0;
    std::vector<std::uint8_t> data{};
    bool complete_access = false;
    std::chrono::milliseconds timeout = kSdoTimeout;
};
struct SdoObjectList {
    std::uint16_t position = 0;
    wire::OdListType list = wire::OdListType::All;
    std::chrono::milliseconds timeout = kSdoTimeout;
};
struct SdoObjectQuery {
    std::uint16_t position = 0;
    std::uint16_t index = 0;
    std::chrono::milliseconds timeout = kSdoTimeout;
};
struct SdoEntryQuery {
    std::uint16_t position = 0;
    std::uint16_t index = 0;
    std::uint8_t subindex = 0;
    std::chrono::milliseconds timeout = kSdoTimeout;
};
// The whole dictionary: the object list (All), each object's description
// and, with `entries`, the description of each of its subindices (0 to the
// max subindex; one the slave does not describe is left out, as IgH does).
struct SdoDictionary {
    std::uint16_t position = 0;
    bool entries = true;
    std::chrono::milliseconds timeout = kSdoTimeout;
};
struct SdoObject {
    wire::ObjectDescription object;
    std::vector<wire::EntryDescription> entries;
};
struct FoeRead {
    std::uint16_t position = 0;
    std::string file{};
    std::uint32_t password = 0;
    std::size_t max_size = kFoeMaxSize;
    std::chrono::milliseconds timeout = kFoeTimeout;
};
struct FoeWrite {
    std::uint16_t position = 0;
    std::string file{};
    std::uint32_t password = 0;
    std::vector<std::uint8_t> data{};
    std::chrono::milliseconds timeout = kFoeTimeout;
};
struct SoeRead {
    std::uint16_t position = 0;
    std::uint8_t drive = 0;
    std::uint16_t idn = 0;
    std::uint8_t elements = wire::soe_elements::kValue;
    std::chrono::milliseconds timeout = kSdoTimeout;
};
struct SoeWrite {
    std::uint16_t position = 0;
    std::uint8_t drive = 0;
    std::uint16_t idn = 0;
    std::uint8_t elements = wire::soe_elements::kValue;
    std::vector<std::uint8_t> data{};
    std::chrono::milliseconds timeout = kSdoTimeout;
};
// FPRD/FPWR at the slave's station address; one datagram (at most 1486 bytes).
struct RegisterRead {
    std::uint16_t position = 0;
    std::uint16_t address = 0;
    std::uint16_t length = 1;
};
struct RegisterWrite {
    std::uint16_t position = 0;
    std::uint16_t address = 0;
    std::vector<std::uint8_t> data{};
};
// Words of the SII EEPROM, as bytes (little-endian words). words 0: from
// word_address to the end marker of the category area (the whole SII when
// word_address is 0). The EEPROM is given back to the PDI afterwards if the
// PDI had it.
struct SiiRead {
    std::uint16_t position = 0;
    std::uint16_t word_address = 0;
    std::uint16_t words = 0;
};
// Guarded: refused (InvalidState) unless MailboxServiceOptions::allow_sii_write;
// data must be whole words; writing into words 0-7 needs a right checksum in
// word 7 and the ENI's vendor id and product code, unless `force`.
struct SiiWrite {
    std::uint16_t position = 0;
    std::uint16_t word_address = 0;
    std::vector<std::uint8_t> data{};
    bool force = false;
};

struct MailboxServiceHooks {
    // Whether the slave (ENI index) is on the bus now; null: all are.
    std::function<bool(std::size_t slave)> present;
    // CoE emergencies go here as coe-emergency events (null: logged).
    master::EventQueue* events = nullptr;
};

struct MailboxServiceOptions {
    std::size_t workers = 2;
    std::size_t max_queued = 256;  // requests waiting, all slaves together
    // How often idle mailboxes are looked at for an emergency (SM1 full):
    // nullopt takes the shortest PollTime of the ENI's slaves (10 ms when none
    // says), 0 switches the poll off.
    std::optional<std::chrono::milliseconds> emergency_poll;
    bool allow_sii_write = false;
};

// A coe-emergency event's numbers: a = slave index, b = error code | error
// register << 16, c = data bytes 0-3 (little-endian), d = data byte 4.
struct CoeEmergencyEvent {
    std::uint32_t slave = 0;
    wire::CoeEmergency emergency;

    master::Event to_event() const;  // kind and a..d only
    static CoeEmergencyEvent from(const master::Event& event);
};

class MailboxService {
public:
    MailboxService(std::shared_ptr<const eni::EniConfig> eni, bus::BusAccess& bus, SlaveMailboxes& mailboxes,
                   MailboxServiceHooks hooks = {}, Clock& clock = steady_clock(), MailboxServiceOptions options = {});
    ~MailboxService();
    MailboxService(const MailboxService&) = delete;
    MailboxService& operator=(const MailboxService&) = delete;

    void sdo_upload(SdoUpload request, Completion<std::vector<std::uint8_t>> done);
    std::future<ServiceResult<std::vector<std::uint8_t>>> sdo_upload(SdoUpload request);
    void sdo_download(SdoDownload request, Completion<void> done);
    std::future<ServiceResult<void>> sdo_download(SdoDownload request);
    void sdo_object_list(SdoObjectList request, Completion<std::vector<std::uint16_t>> done);
    std::future<ServiceResult<std::vector<std::uint16_t>>> sdo_object_list(SdoObjectList request);
    void sdo_object_description(SdoObjectQuery request, Completion<wire::ObjectDescription> done);
    std::future<ServiceResult<wire::ObjectDescription>> sdo_object_description(SdoObjectQuery request);
    void sdo_entry_description(SdoEntryQuery request, Completion<wire::EntryDescription> done);
    std::future<ServiceResult<wire::EntryDescription>> sdo_entry_description(SdoEntryQuery request);
    void sdo_dictionary(SdoDictionary request, Completion<std::vector<SdoObject>> done);
    std::future<ServiceResult<std::vector<SdoObject>>> sdo_dictionary(SdoDictionary request);
    void foe_read(FoeRead request, Completion<std::vector<std::uint8_t>> done);
    std::future<ServiceResult<std::vector<std::uint8_t>>> foe_read(FoeRead request);
    void foe_write(FoeWrite request, Completion<void> done);
    std::future<ServiceResult<void>> foe_write(FoeWrite request);
    void soe_read(SoeRead request, Completion<std::vector<std::uint8_t>> done);
    std::future<ServiceResult<std::vector<std::uint8_t>>> soe_read(SoeRead request);
    void soe_write(SoeWrite request, Completion<void> done);
    std::future<ServiceResult<void>> soe_write(SoeWrite request);
    void register_read(RegisterRead request, Completion<std::vector<std::uint8_t>> done);
    std::future<ServiceResult<std::vector<std::uint8_t>>> register_read(RegisterRead request);
    void register_write(RegisterWrite request, Completion<void> done);
    std::future<ServiceResult<void>> register_write(RegisterWrite request);
    void sii_read(SiiRead request, Completion<std::vector<std::uint8_t>> done);
    std::future<ServiceResult<std::vector<std::uint8_t>>> sii_read(SiiRead request);
    void sii_write(SiiWrite request, Completion<void> done);
    std::future<ServiceResult<void>> sii_write(SiiWrite request);

    // Requests queued or running now.
    std::size_t pending() const;

private:
    class Job;
    struct Context;
    struct SlaveQueue {
        std::deque<std::unique_ptr<Job>> jobs;
        bool running = false;
    };

    // What a request needs besides the slave: the protocol its mailbox must offer (0: none needed).
    template <class T, class Run>
    void submit(std::uint16_t position, std::uint16_t protocol, std::string_view what, Completion<T> done, Run run);
    std::optional<ServiceError> admit(std::uint16_t position, std::uint16_t protocol, std::string_view what);
    ServiceError error(ServiceErrc code, std::uint16_t position, std::string_view detail) const;
    void worker(std::stop_token stop);
    void poll_emergencies(std::stop_token stop);
    void on_emergency(std::size_t slave, const wire::CoeEmergency& emergency);
    std::string slave_text(std::uint16_t position) const;

    std::shared_ptr<const eni::EniConfig> eni_;
    bus::BusAccess& bus_;
    SlaveMailboxes& mailboxes_;
    MailboxServiceHooks hooks_;
    Clock& clock_;
    MailboxServiceOptions options_;
    std::chrono::milliseconds poll_interval_{0};

    mutable std::mutex mutex_;
    std::condition_variable_any wake_;
    std::vector<SlaveQueue> queues_;   // by position
    std::deque<std::uint16_t> ready_;  // slaves with a job waiting and none running
    std::size_t queued_ = 0;           // jobs waiting or running
    bool stopping_ = false;

    std::vector<std::jthread> workers_;  // last: they start once everything above exists
    std::jthread poller_;
};

}  // namespace ecpair::sequencer
