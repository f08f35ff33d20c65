#include "ecpair/sequencer/slave_monitor.hpp"

#include "ecpair/common/bytes.hpp"
#include "ecpair/common/log.hpp"
#include "ecpair/master/master_events.hpp"
#include "ecpair/wire/al_status.hpp"
#include "ecpair/wire/esc_registers.hpp"

namespace ecpair::sequencer {

SlaveMonitor::SlaveMonitor(std::shared_ptr<const eni::EniConfig> eni, bus::BusAccess& bus,
                           master::SlaveStateImage& image, master::EventQueue* events,
                           std::function<bool()> addresses_assigned, std::chrono::milliseconds period,
                           bool report_presence)
    : eni_(std::move(eni)),
      bus_(bus),
      image_(image),
      events_(events),
      addresses_assigned_(std::move(addresses_assigned)),
      period_(period),
      report_presence_(report_presence),
      thread_([this](std::stop_token stop) { run(stop); }) {}

SlaveMonitor::~SlaveMonitor() {
    thread_.request_stop();
    wake_.notify_all();
}

std::uint64_t SlaveMonitor::rounds() const {
    std::lock_guard lock(mutex_);
    return rounds_;
}

void SlaveMonitor::raise(master::EventKind kind, std::uint32_t a, std::uint32_t b, std::uint32_t c) {
    if (events_) events_->raise(kind, a, b, c);
}

void SlaveMonitor::poll_once() {
    // All slaves in one go: the master packs the reads into as few frames as
    // fit, so a round costs a cycle or two and one wake-up, not one per slave.
    std::vector<bus::DatagramRequest> reads;
    reads.reserve(eni_->slaves.size());
    for (const auto& slave : eni_->slaves) {
        reads.push_back(bus::read_request(bus::SlaveAddress::station(slave.info.phys_addr), wire::reg::kAlStatus, 6));
    }
    const auto replies = bus_.exchange_all(reads);
    for (std::size_t i = 0; i < replies.size(); ++i) {
        const auto station = eni_->slaves[i].info.phys_addr;
        const auto& reply = replies[i];
        if (!reply) {
            // An INACTIVE master or a stopping one: nothing to learn now.
            if (reply.error().code == bus::BusErrc::MasterRedStateInactive ||
                reply.error().code == bus::BusErrc::Cancelled) {
                return;
            }
            continue;  // a timeout says nothing about this slave yet; the next round asks again
        }
        master::SlaveStateEntry entry;
        entry.station_address = station;
        entry.present = reply->wkc == 1;
        if (entry.present) {
            entry.al_status = reply->data[0];
            entry.al_status_code = load_le<std::uint16_t>(reply->data, 4);
        }
        const auto previous = image_.set_observed(i, entry);
        if (previous.present != entry.present) {
            logger("slaves")->log(entry.present ? spdlog::level::info : spdlog::level::warn,
                                  "slave {} '{}' (station {}) is {}", i, eni_->slaves[i].info.name, station,
                                  entry.present ? "present" : "absent");
            if (report_presence_) {
                raise(master::events::kSlavePresence, static_cast<std::uint32_t>(i), entry.present ? 1 : 0);
            }
        }
        const wire::AlStatus status{entry.al_status};
        if (entry.present && status.error() && !(previous.present && wire::AlStatus{previous.al_status}.error())) {
            logger("slaves")->warn("slave {} '{}' in {}: 0x{:04x} {}", i, eni_->slaves[i].info.name, status.to_string(),
                                   entry.al_status_code, wire::al_status_code_text(entry.al_status_code));
            raise(master::events::kSlaveStateError, static_cast<std::uint32_t>(i), entry.al_status,
                  entry.al_status_code);
        }
    }
    std::lock_guard lock(mutex_);
    ++rounds_;
}

void SlaveMonitor::run(std::stop_token stop) {
    while (!stop.stop_requested()) {
        {
            std::unique_lock lock(mutex_);
            wake_.wait_for(lock, stop, period_, [] { return false; });
        }
        if (stop.stop_requested()) return;
        if (addresses_assigned_()) poll_once();
    }
}

}  // namespace ecpair::sequencer
