#pragma once
// One slave's mailbox and a small CoE SDO server behind it, as a BusAccess:
// FPWR of SM0 hands a request to the server (WKC 0 while the mailbox is
// "full"), FPRD of 0x080D shows SM1's full bit, FPRD of SM1 hands out the
// next queued reply. The server keeps objects per (index, subindex) and
// answers downloads and uploads in every form the client may use; knobs
// inject mailbox errors, emergencies and a busy SM0.

#include <cstdint>
#include <deque>
#include <map>
#include <optional>
#include <utility>
#include <vector>

#include "ecpair/bus/bus_access.hpp"
#include "ecpair/sequencer/mailbox_transport.hpp"
#include "ecpair/wire/coe.hpp"

namespace ecpair::test {

class FakeMailboxSlave final : public bus::BusAccess {
public:
    static constexpr std::uint16_t kStation = 1001;
    static constexpr std::uint16_t kMailboxLength = 128;

    static sequencer::MailboxChannel channel() {
        return {kStation, {0x1000, kMailboxLength}, {0x1080, kMailboxLength}};
    }

    Expected<bus::DatagramReply, bus::BusError> exchange(const bus::DatagramRequest& request) override;

    // ---- the object dictionary
    std::map<std::pair<std::uint16_t, std::uint8_t>, std::vector<std::uint8_t>> objects;

    // ---- knobs
    std::uint32_t sm0_busy_writes = 0;          // the next n SM0 writes find the mailbox full (WKC 0)
    std::optional<std::uint16_t> mailbox_error;  // answer the next request with this mailbox error
    bool emergency_first = false;               // put an emergency in SM1 before the next answer
    bool answer = true;                         // false: requests are swallowed (timeout)

    // ---- what the client did
    std::vector<wire::SdoMessage> requests;  // every SDO request received, decoded
    std::vector<std::uint8_t> counters;      // the mailbox counter of every request
    std::uint32_t sm0_writes_refused = 0;

private:
    void on_request(const std::vector<std::uint8_t>& buffer);
    void serve(const wire::SdoMessage& request);
    void respond(const wire::SdoMessage& response);
    void post(std::vector<std::uint8_t> message);

    std::deque<std::vector<std::uint8_t>> sm1_;
    // Segmented transfers in progress.
    std::optional<std::pair<std::uint16_t, std::uint8_t>> download_target_;
    std::vector<std::uint8_t> download_data_;
    std::vector<std::uint8_t> upload_rest_;
    bool toggle_ = false;
};

}  // namespace ecpair::test
