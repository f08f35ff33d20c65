// The mailbox service's queue, workers and poll (see the header). A request
// becomes a Job: the function that runs it on a worker and completes it, and
// the one that fails it (refused, cancelled). A slave's queue is "ready"
// while it has a job waiting and none running; a worker takes the oldest
// ready slave, runs its first job without the lock, and puts the slave
// back when more wait. The protocol clients' errors become ServiceErrors
// here, in one place per error type.

#include "ecpair/sequencer/mailbox_service.hpp"

#include <algorithm>

#include <fmt/format.h>

#include "ecpair/bus/sii_reader.hpp"
#include "ecpair/bus/sii_writer.hpp"
#include "ecpair/common/hex.hpp"
#include "ecpair/common/log.hpp"
#include "ecpair/sequencer/foe_client.hpp"
#include "ecpair/sequencer/sdo_client.hpp"
#include "ecpair/sequencer/sdo_information_client.hpp"
#include "ecpair/sequencer/soe_client.hpp"
#include "ecpair/wire/datagram.hpp"
#include "ecpair/wire/esc_registers.hpp"
#include "ecpair/wire/mailbox.hpp"

namespace ecpair::sequencer {
namespace {

constexpr std::chrono::milliseconds kDefaultPoll{10};
constexpr std::chrono::milliseconds kPollRead{100};
constexpr std::uint16_t kSiiCategoryStart = 0x40;
constexpr std::uint16_t kSiiEnd = 0xFFFF;
constexpr std::size_t kSiiMaxWords = 0x8000;  // 64 KiB, the largest EEPROM an ESC addresses
constexpr std::uint16_t kSiiVendorWord = 0x08;
constexpr std::uint16_t kSiiProductWord = 0x0A;
constexpr std::uint16_t kSiiChecksumWord = 7;
constexpr std::uint8_t kEepromPdi = 0x01;  // 0x0500 bit 0: the PDI has the EEPROM

const char* const kInterrupted =
    "this member stopped being ACTIVE (a takeover, a hand-off or its shutdown) during the request: send it "
    "again to the new ACTIVE";

// A bus refusal in the middle of an admitted request is the role change that cut it.
ServiceErrc code_of(bus::BusErrc code) {
    switch (code) {
        case bus::BusErrc::MasterRedStateInactive:
        case bus::BusErrc::Cancelled: return ServiceErrc::Interrupted;
        case bus::BusErrc::InvalidRequest: return ServiceErrc::InvalidParam;
        case bus::BusErrc::Timeout:
        case bus::BusErrc::LinkFailure: return ServiceErrc::Timeout;
    }
    return ServiceErrc::Timeout;
}

std::string with_reason(ServiceErrc code, const std::string& detail) {
    return code == ServiceErrc::Interrupted ? detail + ": " + kInterrupted : detail;
}

}  // namespace

std::string_view to_string(ServiceErrc code) {
    switch (code) {
        case ServiceErrc::MasterRedStateInactive: return "MasterRedStateInactive";
        case ServiceErrc::Interrupted: return "Interrupted";
        case ServiceErrc::InvalidParam: return "InvalidParam";
        case ServiceErrc::SlaveNotPresent: return "SlaveNotPresent";
        case ServiceErrc::NotSupported: return "NotSupported";
        case ServiceErrc::InvalidState: return "InvalidState";
        case ServiceErrc::Timeout: return "Timeout";
        case ServiceErrc::SdoAbort: return "SdoAbort";
        case ServiceErrc::MailboxError: return "MailboxError";
        case ServiceErrc::FoeError: return "FoeError";
        case ServiceErrc::SoeError: return "SoeError";
        case ServiceErrc::EoeError: return "EoeError";
        case ServiceErrc::ProtocolError: return "ProtocolError";
        case ServiceErrc::NoResponse: return "NoResponse";
        case ServiceErrc::Busy: return "Busy";
        case ServiceErrc::Cancelled: return "Cancelled";
    }
    return "?";
}

master::Event CoeEmergencyEvent::to_event() const {
    master::Event event;
    event.kind = master::events::kCoeEmergency;
    event.a = slave;
    event.b = emergency.error_code | (static_cast<std::uint32_t>(emergency.error_register) << 16);
    event.c = load_le<std::uint32_t>(emergency.data, 0);
    event.d = emergency.data[4];
    return event;
}

CoeEmergencyEvent CoeEmergencyEvent::from(const master::Event& event) {
    CoeEmergencyEvent e;
    e.slave = event.a;
    e.emergency.error_code = static_cast<std::uint16_t>(event.b);
    e.emergency.error_register = static_cast<std::uint8_t>(event.b >> 16);
    store_le<std::uint32_t>(e.emergency.data, 0, event.c);
    e.emergency.data[4] = static_cast<std::uint8_t>(event.d);
    return e;
}

class MailboxService::Job {
public:
    // Runs the request; what it returns completes it.
    std::function<std::function<void()>(Context&)> run;
    std::function<void(ServiceError)> fail;  // completes it with an error
};

struct MailboxService::Context {
    MailboxService& service;
    std::uint16_t position;
    SlaveMailbox* mailbox;  // null for register and SII access
    std::stop_token stop;

    ServiceError error(ServiceErrc code, const std::string& detail) const {
        return service.error(code, position, with_reason(code, detail));
    }
    ServiceError from(const SdoError& e) const {
        ServiceErrc code = ServiceErrc::ProtocolError;
        switch (e.failure) {
            case SdoFailure::Abort: code = ServiceErrc::SdoAbort; break;
            case SdoFailure::MailboxError: code = ServiceErrc::MailboxError; break;
            case SdoFailure::Timeout: code = ServiceErrc::Timeout; break;
            case SdoFailure::Protocol: code = ServiceErrc::ProtocolError; break;
            case SdoFailure::TooLong: code = ServiceErrc::InvalidParam; break;
            case SdoFailure::Bus: code = e.bus_error ? code_of(*e.bus_error) : ServiceErrc::Timeout; break;
            case SdoFailure::Stopped: code = ServiceErrc::Cancelled; break;
        }
        auto out = error(code, e.message);
        out.abort_code = e.abort_code;
        out.mailbox_error = e.mailbox_error;
        return out;
    }
    // `refused`: what the protocol's own error is (FoeError, SoeError, EoeError).
    ServiceError from(const ProtocolError& e, ServiceErrc refused) const {
        ServiceErrc code = ServiceErrc::ProtocolError;
        switch (e.failure) {
            case ProtocolFailure::Refused: code = refused; break;
            case ProtocolFailure::MailboxError: code = ServiceErrc::MailboxError; break;
            case ProtocolFailure::Timeout: code = ServiceErrc::Timeout; break;
            case ProtocolFailure::Malformed: code = ServiceErrc::ProtocolError; break;
            case ProtocolFailure::TooLong: code = ServiceErrc::InvalidParam; break;
            case ProtocolFailure::Bus: code = e.bus_error ? code_of(*e.bus_error) : ServiceErrc::Timeout; break;
            case ProtocolFailure::Stopped: code = ServiceErrc::Cancelled; break;
        }
        auto out = error(code, e.message);
        out.mailbox_error = e.mailbox_error;
        if (code == ServiceErrc::FoeError) out.foe_error = e.code;
        if (code == ServiceErrc::SoeError) out.soe_error = static_cast<std::uint16_t>(e.code);
        if (code == ServiceErrc::EoeError) out.eoe_result = static_cast<std::uint16_t>(e.code);
        return out;
    }
    ServiceError from(const bus::BusError& e, const std::string& what) const {
        return error(code_of(e.code), fmt::format("{}: {}", what, e.message));
    }
    std::uint16_t station() const { return service.eni_->slaves[position].info.phys_addr; }
};

MailboxService::MailboxService(std::shared_ptr<const eni::EniConfig> eni, bus::BusAccess& bus,
                               SlaveMailboxes& mailboxes, MailboxServiceHooks hooks, Clock& clock,
                               MailboxServiceOptions options)
    : eni_(std::move(eni)),
      bus_(bus),
      mailboxes_(mailboxes),
      hooks_(std::move(hooks)),
      clock_(clock),
      options_(options),
      queues_(eni_->slaves.size()) {
    if (options_.emergency_poll) {
        poll_interval_ = *options_.emergency_poll;
    } else {
        std::optional<std::uint32_t> shortest;
        for (const auto& slave : eni_->slaves) {
            if (slave.mailbox && slave.mailbox->poll_time_ms && *slave.mailbox->poll_time_ms > 0) {
                shortest = std::min(shortest.value_or(*slave.mailbox->poll_time_ms), *slave.mailbox->poll_time_ms);
            }
        }
        poll_interval_ = shortest ? std::chrono::milliseconds(*shortest) : kDefaultPoll;
    }
    mailboxes_.set_emergency_handler(
        [this](std::size_t slave, const wire::CoeEmergency& emergency) { on_emergency(slave, emergency); });
    for (std::size_t i = 0; i < std::max<std::size_t>(options_.workers, 1); ++i) {
        workers_.emplace_back([this](std::stop_token stop) { worker(stop); });
    }
    if (poll_interval_.count() > 0) poller_ = std::jthread([this](std::stop_token stop) { poll_emergencies(stop); });
}

MailboxService::~MailboxService() {
    std::vector<std::unique_ptr<Job>> cancelled;
    {
        std::lock_guard lock(mutex_);
        stopping_ = true;
        for (std::size_t position = 0; position < queues_.size(); ++position) {
            for (auto& job : queues_[position].jobs) cancelled.push_back(std::move(job));
            queues_[position].jobs.clear();
        }
        ready_.clear();
    }
    for (auto& job : cancelled) job->fail(ServiceError{ServiceErrc::Cancelled, 0, {}, 0, 0, 0, 0, 0,
                                                       "Cancelled: the mailbox service is shutting down"});
    for (auto& w : workers_) w.request_stop();
    if (poller_.joinable()) poller_.request_stop();
    wake_.notify_all();
}

std::size_t MailboxService::pending() const {
    std::lock_guard lock(mutex_);
    return queued_;
}

std::string MailboxService::slave_text(std::uint16_t position) const {
    if (position >= eni_->slaves.size()) return fmt::format("slave {}", position);
    const auto& info = eni_->slaves[position].info;
    return fmt::format("slave {} '{}' (station {})", position, info.name, info.phys_addr);
}

ServiceError MailboxService::error(ServiceErrc code, std::uint16_t position, std::string_view detail) const {
    ServiceError e;
    e.code = code;
    e.position = position;
    e.slave = slave_text(position);
    e.message = fmt::format("{}: {}: {}", to_string(code), e.slave, detail);
    return e;
}

std::optional<ServiceError> MailboxService::admit(std::uint16_t position, std::uint16_t protocol,
                                                  std::string_view what) {
    if (position >= eni_->slaves.size()) {
        return error(ServiceErrc::InvalidParam, position,
                     fmt::format("{}: no slave at position {}: the ENI configures {} (positions 0..{})", what,
                                 position, eni_->slaves.size(), eni_->slaves.empty() ? 0 : eni_->slaves.size() - 1));
    }
    if (const auto refusal = bus_.refusal()) {
        if (*refusal == bus::BusErrc::MasterRedStateInactive) {
            return error(ServiceErrc::MasterRedStateInactive, position,
                         fmt::format("{}: this member is INACTIVE and must not talk to the slaves: ask the ACTIVE", what));
        }
        return error(ServiceErrc::Cancelled, position, fmt::format("{}: the master is shutting down", what));
    }
    if (hooks_.present && !hooks_.present(position)) {
        return error(ServiceErrc::SlaveNotPresent, position, fmt::format("{}: the slave is not on the bus", what));
    }
    if (protocol != 0) {
        const auto* mailbox = mailboxes_.find(position);
        if (mailbox == nullptr) {
            return error(ServiceErrc::NotSupported, position, fmt::format("{}: the slave has no mailbox", what));
        }
        if (!mailbox->supports(static_cast<eni::MailboxProtocol>(protocol))) {
            return error(ServiceErrc::NotSupported, position,
                         fmt::format("{}: the ENI does not give the slave this mailbox protocol", what));
        }
    }
    return std::nullopt;
}

template <class T, class Run>
void MailboxService::submit(std::uint16_t position, std::uint16_t protocol, std::string_view what, Completion<T> done,
                            Run run) {
    if (auto refused = admit(position, protocol, what)) {
        done(unexpected(std::move(*refused)));
        return;
    }
    auto completion = std::make_shared<Completion<T>>(std::move(done));
    auto job = std::make_unique<Job>();
    job->run = [completion, run = std::move(run)](Context& context) mutable -> std::function<void()> {
        return [completion, result = std::make_shared<ServiceResult<T>>(run(context))] {
            (*completion)(std::move(*result));
        };
    };
    job->fail = [completion](ServiceError e) { (*completion)(unexpected(std::move(e))); };
    std::optional<ServiceError> refused;
    {
        std::lock_guard lock(mutex_);
        if (stopping_) {
            refused = error(ServiceErrc::Cancelled, position, "the mailbox service is shutting down");
        } else if (queued_ >= options_.max_queued) {
            refused = error(ServiceErrc::Busy, position,
                            fmt::format("{}: {} requests are waiting already; try again later", what, queued_));
        } else {
            auto& queue = queues_[position];
            queue.jobs.push_back(std::move(job));
            ++queued_;
            if (!queue.running && queue.jobs.size() == 1) ready_.push_back(position);
        }
    }
    if (refused) {
        job->fail(std::move(*refused));
        return;
    }
    wake_.notify_one();
}

void MailboxService::worker(std::stop_token stop) {
    for (;;) {
        std::unique_ptr<Job> job;
        std::uint16_t position = 0;
        {
            std::unique_lock lock(mutex_);
            if (!wake_.wait(lock, stop, [this] { return !ready_.empty(); })) return;
            position = ready_.front();
            ready_.pop_front();
            auto& queue = queues_[position];
            job = std::move(queue.jobs.front());
            queue.jobs.pop_front();
            queue.running = true;
        }
        Context context{*this, position, mailboxes_.find(position), stop};
        std::function<void()> complete;
        if (bus_.refusal()) {
            // Admitted while ACTIVE, still queued when the role changed.
            complete = [&job, error = context.error(ServiceErrc::Interrupted, "still queued")] { job->fail(error); };
        } else {
            complete = job->run(context);
        }
        // Done before its completion runs (pending() no longer counts it); the
        // slave's next request starts only after the completion, so a slave's
        // completions come in order.
        {
            std::lock_guard lock(mutex_);
            --queued_;
        }
        complete();
        job.reset();
        {
            std::lock_guard lock(mutex_);
            auto& queue = queues_[position];
            queue.running = false;
            if (!queue.jobs.empty() && !stopping_) {
                ready_.push_back(position);
                wake_.notify_one();
            }
        }
    }
}

void MailboxService::on_emergency(std::size_t slave, const wire::CoeEmergency& emergency) {
    if (hooks_.events) {
        const auto event = CoeEmergencyEvent{static_cast<std::uint32_t>(slave), emergency}.to_event();
        hooks_.events->raise(event.kind, event.a, event.b, event.c, event.d);
        return;
    }
    logger("sequencer")->warn("{}: CoE emergency 0x{:04x} ({}), error register 0x{:02x}, data {}",
                              slave_text(static_cast<std::uint16_t>(slave)), emergency.error_code,
                              wire::emergency_error_class(emergency.error_code), emergency.error_register,
                              to_hex(emergency.data, " "));
}

// Every poll_interval_: one batch reads SM1's status of every idle mailbox
// that offers CoE; a full one is read (its session still held) and handed to
// the transport, which raises an emergency and drops anything else.
void MailboxService::poll_emergencies(std::stop_token stop) {
    std::mutex sleep_mutex;
    std::condition_variable_any sleeper;  // nobody notifies it: it wakes after the interval, or at once on stop
    for (;;) {
        {
            std::unique_lock lock(sleep_mutex);
            sleeper.wait_for(lock, stop, poll_interval_, [] { return false; });
            if (stop.stop_requested()) return;
        }
        if (bus_.refusal()) continue;
        std::vector<SlaveMailbox::Session> sessions;
        std::vector<bus::DatagramRequest> requests;
        for (std::size_t i = 0; i < eni_->slaves.size(); ++i) {
            auto* mailbox = mailboxes_.find(i);
            if (mailbox == nullptr || !mailbox->supports(eni::kCoE)) continue;
            if (hooks_.present && !hooks_.present(i)) continue;
            auto session = mailbox->try_open();
            if (!session) continue;
            sessions.push_back(std::move(*session));
            requests.push_back(bus::read_request(bus::SlaveAddress::station(mailbox->channel().station), wire::kSm1StatusRegister, 1));
        }
        if (requests.empty()) continue;
        const auto replies = bus_.exchange_all(requests);
        for (std::size_t k = 0; k < replies.size() && k < sessions.size(); ++k) {
            const auto& reply = replies[k];
            if (!reply || reply->wkc != 1 || reply->data.empty() || (reply->data[0] & wire::kSmStatusMailboxFull) == 0) continue;
            auto& transport = sessions[k].transport();
            auto buffer = transport.receive(clock_.now() + kPollRead, stop);
            if (buffer) transport.dispatch_unsolicited(*buffer);
        }
    }
}

// ---- the requests

void MailboxService::sdo_upload(SdoUpload r, Completion<std::vector<std::uint8_t>> done) {
    submit<std::vector<std::uint8_t>>(
        r.position, eni::kCoE, fmt::format("SDO 0x{:04x}:{:02x} upload", r.index, r.subindex), std::move(done),
        [this, r](Context& c) -> ServiceResult<std::vector<std::uint8_t>> {
            auto session = c.mailbox->open();
            SdoClient sdo(session.transport(), clock_);
            auto value = sdo.upload(r.index, r.subindex, r.complete_access, r.timeout, c.stop);
            if (!value) return unexpected(c.from(value.error()));
            return std::move(*value);
        });
}

void MailboxService::sdo_download(SdoDownload r, Completion<void> done) {
    if (r.data.empty()) {
        done(unexpected(error(ServiceErrc::InvalidParam, r.position,
                              fmt::format("SDO 0x{:04x}:{:02x} download: no data to write", r.index, r.subindex))));
        return;
    }
    submit<void>(r.position, eni::kCoE, fmt::format("SDO 0x{:04x}:{:02x} download", r.index, r.subindex),
                 std::move(done), [this, r = std::move(r)](Context& c) -> ServiceResult<void> {
                     auto session = c.mailbox->open();
                     SdoClient sdo(session.transport(), clock_);
                     auto written = sdo.download(r.index, r.subindex, r.data, r.complete_access, r.timeout, c.stop);
                     if (!written) return unexpected(c.from(written.error()));
                     return {};
                 });
}

void MailboxService::sdo_object_list(SdoObjectList r, Completion<std::vector<std::uint16_t>> done) {
    submit<std::vector<std::uint16_t>>(
        r.position, eni::kCoE, "SDO Information object list", std::move(done),
        [this, r](Context& c) -> ServiceResult<std::vector<std::uint16_t>> {
            auto session = c.mailbox->open();
            SdoInformationClient info(session.transport(), clock_);
            auto list = info.object_list(r.list, r.timeout, c.stop);
            if (!list) return unexpected(c.from(list.error()));
            return std::move(*list);
        });
}

void MailboxService::sdo_object_description(SdoObjectQuery r, Completion<wire::ObjectDescription> done) {
    submit<wire::ObjectDescription>(
        r.position, eni::kCoE, fmt::format("SDO Information object 0x{:04x}", r.index), std::move(done),
        [this, r](Context& c) -> ServiceResult<wire::ObjectDescription> {
            auto session = c.mailbox->open();
            SdoInformationClient info(session.transport(), clock_);
            auto description = info.object_description(r.index, r.timeout, c.stop);
            if (!description) return unexpected(c.from(description.error()));
            return std::move(*description);
        });
}

void MailboxService::sdo_entry_description(SdoEntryQuery r, Completion<wire::EntryDescription> done) {
    submit<wire::EntryDescription>(
        r.position, eni::kCoE, fmt::format("SDO Information entry 0x{:04x}:{:02x}", r.index, r.subindex),
        std::move(done), [this, r](Context& c) -> ServiceResult<wire::EntryDescription> {
            auto session = c.mailbox->open();
            SdoInformationClient info(session.transport(), clock_);
            auto description = info.entry_description(r.index, r.subindex, r.timeout, c.stop);
            if (!description) return unexpected(c.from(description.error()));
            return std::move(*description);
        });
}

void MailboxService::sdo_dictionary(SdoDictionary r, Completion<std::vector<SdoObject>> done) {
    submit<std::vector<SdoObject>>(
        r.position, eni::kCoE, "SDO Information dictionary", std::move(done),
        [this, r](Context& c) -> ServiceResult<std::vector<SdoObject>> {
            auto session = c.mailbox->open();
            SdoInformationClient info(session.transport(), clock_);
            auto list = info.object_list(wire::OdListType::All, r.timeout, c.stop);
            if (!list) return unexpected(c.from(list.error()));
            std::vector<SdoObject> dictionary;
            dictionary.reserve(list->size());
            for (const auto index : *list) {
                auto object = info.object_description(index, r.timeout, c.stop);
                // An object the slave lists but does not describe is left out, as IgH's tool does.
                if (!object && object.error().failure == SdoFailure::Abort) continue;
                if (!object) return unexpected(c.from(object.error()));
                SdoObject entry{std::move(*object), {}};
                for (unsigned sub = 0; r.entries && sub <= entry.object.max_subindex; ++sub) {
                    auto description =
                        info.entry_description(index, static_cast<std::uint8_t>(sub), r.timeout, c.stop);
                    if (!description && description.error().failure == SdoFailure::Abort) continue;
                    if (!description) return unexpected(c.from(description.error()));
                    entry.entries.push_back(std::move(*description));
                }
                dictionary.push_back(std::move(entry));
            }
            return dictionary;
        });
}

void MailboxService::foe_read(FoeRead r, Completion<std::vector<std::uint8_t>> done) {
    if (r.file.empty()) {
        done(unexpected(error(ServiceErrc::InvalidParam, r.position, "FoE read: no file name")));
        return;
    }
    submit<std::vector<std::uint8_t>>(
        r.position, eni::kFoE, fmt::format("FoE read '{}'", r.file), std::move(done),
        [this, r](Context& c) -> ServiceResult<std::vector<std::uint8_t>> {
            auto session = c.mailbox->open();
            FoeClient foe(session.transport(), clock_);
            auto file = foe.read(r.file, r.password, r.max_size, r.timeout, c.stop);
            if (!file) return unexpected(c.from(file.error(), ServiceErrc::FoeError));
            return std::move(*file);
        });
}

void MailboxService::foe_write(FoeWrite r, Completion<void> done) {
    if (r.file.empty()) {
        done(unexpected(error(ServiceErrc::InvalidParam, r.position, "FoE write: no file name")));
        return;
    }
    submit<void>(r.position, eni::kFoE, fmt::format("FoE write '{}'", r.file), std::move(done),
                 [this, r = std::move(r)](Context& c) -> ServiceResult<void> {
                     auto session = c.mailbox->open();
                     FoeClient foe(session.transport(), clock_);
                     auto written = foe.write(r.file, r.password, r.data, r.timeout, c.stop);
                     if (!written) return unexpected(c.from(written.error(), ServiceErrc::FoeError));
                     return {};
                 });
}

void MailboxService::soe_read(SoeRead r, Completion<std::vector<std::uint8_t>> done) {
    submit<std::vector<std::uint8_t>>(
        r.position, eni::kSoE, fmt::format("SoE read {} of drive {}", wire::idn_text(r.idn), r.drive), std::move(done),
        [this, r](Context& c) -> ServiceResult<std::vector<std::uint8_t>> {
            auto session = c.mailbox->open();
            SoeClient soe(session.transport(), clock_);
            auto value = soe.read(r.drive, r.idn, r.elements, r.timeout, c.stop);
            if (!value) return unexpected(c.from(value.error(), ServiceErrc::SoeError));
            return std::move(*value);
        });
}

void MailboxService::soe_write(SoeWrite r, Completion<void> done) {
    submit<void>(r.position, eni::kSoE, fmt::format("SoE write {} of drive {}", wire::idn_text(r.idn), r.drive),
                 std::move(done), [this, r = std::move(r)](Context& c) -> ServiceResult<void> {
                     auto session = c.mailbox->open();
                     SoeClient soe(session.transport(), clock_);
                     auto written = soe.write(r.drive, r.idn, r.elements, r.data, r.timeout, c.stop);
                     if (!written) return unexpected(c.from(written.error(), ServiceErrc::SoeError));
                     return {};
                 });
}

void MailboxService::register_read(RegisterRead r, Completion<std::vector<std::uint8_t>> done) {
    const auto what = fmt::format("register read of {} byte(s) at 0x{:04x}", r.length, r.address);
    if (r.length == 0 || r.length > wire::kMaxDatagramData || r.address + std::size_t{r.length} > 0x10000) {
        done(unexpected(error(ServiceErrc::InvalidParam, r.position,
                              fmt::format("{}: 1..{} bytes within the 64 KiB address space", what,
                                          wire::kMaxDatagramData))));
        return;
    }
    submit<std::vector<std::uint8_t>>(
        r.position, 0, what, std::move(done), [this, r, what](Context& c) -> ServiceResult<std::vector<std::uint8_t>> {
            auto reply = bus::read_register(bus_, bus::SlaveAddress::station(c.station()), r.address, r.length);
            if (!reply) return unexpected(c.from(reply.error(), what));
            if (reply->wkc != 1) {
                return unexpected(c.error(ServiceErrc::NoResponse, fmt::format("{}: WKC {} (no answer)", what, reply->wkc)));
            }
            return std::move(reply->data);
        });
}

void MailboxService::register_write(RegisterWrite r, Completion<void> done) {
    const auto what = fmt::format("register write of {} byte(s) at 0x{:04x}", r.data.size(), r.address);
    if (r.data.empty() || r.data.size() > wire::kMaxDatagramData || r.address + r.data.size() > 0x10000) {
        done(unexpected(error(ServiceErrc::InvalidParam, r.position,
                              fmt::format("{}: 1..{} bytes within the 64 KiB address space", what,
                                          wire::kMaxDatagramData))));
        return;
    }
    submit<void>(r.position, 0, what, std::move(done), [this, r = std::move(r), what](Context& c) -> ServiceResult<void> {
        auto reply = bus::write_register(bus_, bus::SlaveAddress::station(c.station()), r.address, r.data);
        if (!reply) return unexpected(c.from(reply.error(), what));
        if (reply->wkc != 1) {
            return unexpected(c.error(ServiceErrc::NoResponse, fmt::format("{}: WKC {} (no answer)", what, reply->wkc)));
        }
        return {};
    });
}

void MailboxService::sii_read(SiiRead r, Completion<std::vector<std::uint8_t>> done) {
    submit<std::vector<std::uint8_t>>(
        r.position, 0, "SII read", std::move(done), [this, r](Context& c) -> ServiceResult<std::vector<std::uint8_t>> {
            const auto slave = bus::SlaveAddress::station(c.station());
            const std::string what = "SII read";
            // Who has the EEPROM now: it is given back to the PDI afterwards if the PDI had it.
            auto config = bus::read_register(bus_, slave, wire::reg::kSiiConfig, 1);
            if (!config) return unexpected(c.from(config.error(), what));
            if (config->wkc != 1) return unexpected(c.error(ServiceErrc::NoResponse, what + ": the slave does not answer"));
            const bool pdi_had_it = (config->data[0] & kEepromPdi) != 0;
            bus::SiiReader reader(bus_);
            std::vector<std::uint16_t> words;
            const auto read = [&](std::uint16_t address, std::size_t count) -> std::optional<ServiceError> {
                auto chunk = reader.read_words(slave, address, count);
                if (!chunk) return c.from(chunk.error(), what);
                words.insert(words.end(), chunk->begin(), chunk->end());
                return std::nullopt;
            };
            std::optional<ServiceError> failed;
            if (r.words > 0) {
                failed = read(r.word_address, r.words);
            } else {
                // The fixed area up to the categories, then category by category to the end marker.
                std::uint16_t address = r.word_address;
                if (address < kSiiCategoryStart) failed = read(address, kSiiCategoryStart - address);
                address = std::max(address, kSiiCategoryStart);
                while (!failed && words.size() < kSiiMaxWords) {
                    failed = read(address, 2);
                    if (failed || words[words.size() - 2] == kSiiEnd) break;
                    const std::uint16_t size = words.back();
                    address = static_cast<std::uint16_t>(address + 2);
                    if (size > 0 && address + std::size_t{size} <= kSiiMaxWords) failed = read(address, size);
                    address = static_cast<std::uint16_t>(address + size);
                }
            }
            if (pdi_had_it) (void)bus::write_register(bus_, slave, wire::reg::kSiiConfig, {kEepromPdi});
            if (failed) return unexpected(std::move(*failed));
            std::vector<std::uint8_t> bytes(words.size() * 2);
            for (std::size_t i = 0; i < words.size(); ++i) store_le<std::uint16_t>(bytes, 2 * i, words[i]);
            return bytes;
        });
}

void MailboxService::sii_write(SiiWrite r, Completion<void> done) {
    const std::string what = fmt::format("SII write of {} byte(s) at word 0x{:04x}", r.data.size(), r.word_address);
    const auto refuse = [&](ServiceErrc code, const std::string& why) {
        done(unexpected(error(code, r.position, what + ": " + why)));
    };
    if (!options_.allow_sii_write) {
        return refuse(ServiceErrc::InvalidState, "SII writes are not allowed on this master (allow_sii_write)");
    }
    if (r.data.empty() || r.data.size() % 2 != 0 || r.word_address + r.data.size() / 2 > kSiiMaxWords) {
        return refuse(ServiceErrc::InvalidParam, "the data must be whole 16-bit words within the EEPROM");
    }
    if (r.position < eni_->slaves.size() && r.word_address <= kSiiChecksumWord && !r.force) {
        // The configuration area (words 0-7) is written whole, with its checksum, for the slave in the ENI.
        if (r.word_address != 0 || r.data.size() < 2 * (kSiiChecksumWord + 1)) {
            return refuse(ServiceErrc::InvalidParam,
                          "writes into words 0-7 must cover all eight (with the checksum in word 7), or use force");
        }
        std::vector<std::uint16_t> head;
        for (std::size_t i = 0; i < kSiiChecksumWord; ++i) head.push_back(load_le<std::uint16_t>(r.data, 2 * i));
        const std::uint8_t checksum = bus::sii_configuration_crc(head);
        if (r.data[2 * kSiiChecksumWord] != checksum) {
            return refuse(ServiceErrc::InvalidParam,
                          fmt::format("the checksum in word 7 is 0x{:02x}, the words 0-6 give 0x{:02x}",
                                      r.data[2 * kSiiChecksumWord], checksum));
        }
        const auto& info = eni_->slaves[r.position].info;
        if (r.data.size() >= 2 * (kSiiProductWord + 2)) {
            const auto vendor = load_le<std::uint32_t>(r.data, 2 * kSiiVendorWord);
            const auto product = load_le<std::uint32_t>(r.data, 2 * kSiiProductWord);
            if (vendor != info.vendor_id || product != info.product_code) {
                return refuse(ServiceErrc::InvalidParam,
                              fmt::format("the image is for vendor 0x{:08x} product 0x{:08x}, the ENI configures "
                                          "vendor 0x{:08x} product 0x{:08x} here, or use force",
                                          vendor, product, info.vendor_id, info.product_code));
            }
        }
    }
    submit<void>(r.position, 0, what, std::move(done), [this, r = std::move(r), what](Context& c) -> ServiceResult<void> {
        bus::SiiWriter writer(bus_);
        const auto slave = bus::SlaveAddress::station(c.station());
        for (std::size_t i = 0; i < r.data.size() / 2; ++i) {
            const auto word = static_cast<std::uint16_t>(r.word_address + i);
            if (auto written = writer.write_word(slave, word, load_le<std::uint16_t>(r.data, 2 * i)); !written) {
                return unexpected(c.from(written.error(), fmt::format("{} (at word 0x{:04x})", what, word)));
            }
            if (c.stop.stop_requested()) return unexpected(c.error(ServiceErrc::Cancelled, what + ": stopped"));
        }
        return {};
    });
}

// ---- the futures: each kind once, through its completion.

namespace {

template <class T, class Request>
std::future<ServiceResult<T>> as_future(MailboxService& service, Request request,
                                        void (MailboxService::*call)(Request, Completion<T>)) {
    auto promise = std::make_shared<std::promise<ServiceResult<T>>>();
    auto future = promise->get_future();
    (service.*call)(std::move(request), [promise](ServiceResult<T> result) { promise->set_value(std::move(result)); });
    return future;
}

}  // namespace

std::future<ServiceResult<std::vector<std::uint8_t>>> MailboxService::sdo_upload(SdoUpload r) {
    return as_future<std::vector<std::uint8_t>, SdoUpload>(*this, std::move(r), &MailboxService::sdo_upload);
}
std::future<ServiceResult<void>> MailboxService::sdo_download(SdoDownload r) {
    return as_future<void, SdoDownload>(*this, std::move(r), &MailboxService::sdo_download);
}
std::future<ServiceResult<std::vector<std::uint16_t>>> MailboxService::sdo_object_list(SdoObjectList r) {
    return as_future<std::vector<std::uint16_t>, SdoObjectList>(*this, std::move(r), &MailboxService::sdo_object_list);
}
std::future<ServiceResult<wire::ObjectDescription>> MailboxService::sdo_object_description(SdoObjectQuery r) {
    return as_future<wire::ObjectDescription, SdoObjectQuery>(*this, std::move(r),
                                                              &MailboxService::sdo_object_description);
}
std::future<ServiceResult<wire::EntryDescription>> MailboxService::sdo_entry_description(SdoEntryQuery r) {
    return as_future<wire::EntryDescription, SdoEntryQuery>(*this, std::move(r), &MailboxService::sdo_entry_description);
}
std::future<ServiceResult<std::vector<SdoObject>>> MailboxService::sdo_dictionary(SdoDictionary r) {
    return as_future<std::vector<SdoObject>, SdoDictionary>(*this, std::move(r), &MailboxService::sdo_dictionary);
}
std::future<ServiceResult<std::vector<std::uint8_t>>> MailboxService::foe_read(FoeRead r) {
    return as_future<std::vector<std::uint8_t>, FoeRead>(*this, std::move(r), &MailboxService::foe_read);
}
std::future<ServiceResult<void>> MailboxService::foe_write(FoeWrite r) {
    return as_future<void, FoeWrite>(*this, std::move(r), &MailboxService::foe_write);
}
std::future<ServiceResult<std::vector<std::uint8_t>>> MailboxService::soe_read(SoeRead r) {
    return as_future<std::vector<std::uint8_t>, SoeRead>(*this, std::move(r), &MailboxService::soe_read);
}
std::future<ServiceResult<void>> MailboxService::soe_write(SoeWrite r) {
    return as_future<void, SoeWrite>(*this, std::move(r), &MailboxService::soe_write);
}
std::future<ServiceResult<std::vector<std::uint8_t>>> MailboxService::register_read(RegisterRead r) {
    return as_future<std::vector<std::uint8_t>, RegisterRead>(*this, std::move(r), &MailboxService::register_read);
}
std::future<ServiceResult<void>> MailboxService::register_write(RegisterWrite r) {
    return as_future<void, RegisterWrite>(*this, std::move(r), &MailboxService::register_write);
}
std::future<ServiceResult<std::vector<std::uint8_t>>> MailboxService::sii_read(SiiRead r) {
    return as_future<std::vector<std::uint8_t>, SiiRead>(*this, std::move(r), &MailboxService::sii_read);
}
std::future<ServiceResult<void>> MailboxService::sii_write(SiiWrite r) {
    return as_future<void, SiiWrite>(*this, std::move(r), &MailboxService::sii_write);
}

}  // namespace ecpair::sequencer
