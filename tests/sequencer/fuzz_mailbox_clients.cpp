// Fuzzes the mailbox protocol clients' handling of what slaves put into
// SM1. The input: byte 0 chooses the client (bits 4-7: 0 SDO, 1 SDO
// Information object list, 2 entry description, 3 FoE read, 4 FoE write,
// 5 SoE read, 6 SoE write of 300 bytes, 7 EoE set IP; the SDO transfer in
// bits 0-1: upload, download of 2 or of 300 bytes; bit 2: CompleteAccess)
// and how replies appear (bit 3 clear: one per request written to SM0; set:
// all of them from the first request on, so unsolicited messages come
// first); the rest is a sequence of replies, each a length byte followed by
// that many bytes of SM1 content (zero padded to the mailbox size). When the
// replies run out the slave goes silent and the transfer must end with a
// timeout: never a crash, a hang or a read past a buffer.

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "ecpair/common/log.hpp"
#include "ecpair/sequencer/eoe_client.hpp"
#include "ecpair/sequencer/foe_client.hpp"
#include "ecpair/sequencer/sdo_client.hpp"
#include "ecpair/sequencer/sdo_information_client.hpp"
#include "ecpair/sequencer/soe_client.hpp"
#include "fakes.hpp"

namespace {

constexpr std::uint16_t kStation = 1001;
constexpr std::uint16_t kSm0 = 0x1000;
constexpr std::uint16_t kSm1 = 0x1080;
constexpr std::uint16_t kLength = 128;

class ReplayedSlave final : public ecpair::bus::BusAccess {
public:
    ReplayedSlave(const std::uint8_t* data, std::size_t size, bool free_flowing)
        : data_(data), size_(size), free_flowing_(free_flowing) {}

    ecpair::Expected<ecpair::bus::DatagramReply, ecpair::bus::BusError> exchange(
        const ecpair::bus::DatagramRequest& request) override {
        const auto ado = static_cast<std::uint16_t>(request.address >> 16);
        ecpair::bus::DatagramReply reply{request.data, 0};
        if (request.command == ecpair::wire::Command::Fpwr && ado == kSm0) {
            ++credits_;
            reply.wkc = 1;
        } else if (request.command == ecpair::wire::Command::Fprd && ado == 0x080D && !reply.data.empty()) {
            reply.data[0] = available() ? 0x08 : 0x00;
            reply.wkc = 1;
        } else if (request.command == ecpair::wire::Command::Fprd && ado == kSm1 && available()) {
            const std::size_t length = std::min<std::size_t>(data_[offset_], size_ - offset_ - 1);
            std::fill(reply.data.begin(), reply.data.end(), std::uint8_t{0});
            std::copy_n(data_ + offset_ + 1, std::min<std::size_t>(length, reply.data.size()), reply.data.begin());
            offset_ += 1 + length;
            if (!free_flowing_) --credits_;
            reply.wkc = 1;
        }
        return reply;
    }

private:
    bool available() const { return credits_ > 0 && offset_ < size_; }

    const std::uint8_t* data_;
    std::size_t size_;
    bool free_flowing_;
    std::size_t offset_ = 0;
    std::size_t credits_ = 0;  // replies the client's requests have released
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    static const bool quiet = ecpair::set_log_level("off");
    (void)quiet;
    if (size == 0) return 0;
    ReplayedSlave slave(data + 1, size - 1, (data[0] & 0x08) != 0);
    ecpair::test::VirtualClock clock;
    ecpair::sequencer::MailboxTransport transport(slave, clock, {kStation, {kSm0, kLength}, {kSm1, kLength}});
    transport.set_emergency_handler([](const ecpair::wire::CoeEmergency&) {});
    const bool complete_access = (data[0] & 0x04) != 0;
    const auto timeout = std::chrono::milliseconds(20);
    switch (data[0] >> 4) {
        case 0: {
            ecpair::sequencer::SdoClient client(transport, clock);
            switch (data[0] & 0x03) {
                case 0: (void)client.upload(0x1c12, 0, complete_access, timeout); break;
                case 1: (void)client.download(0x6060, 0, std::vector<std::uint8_t>{1, 2}, complete_access, timeout); break;
                default:
                    (void)client.download(0x2000, 1, std::vector<std::uint8_t>(300, 0x5a), complete_access, timeout);
                    break;
            }
            break;
        }
        case 1: (void)ecpair::sequencer::SdoInformationClient(transport, clock).object_list(ecpair::wire::OdListType::All, timeout); break;
        case 2: (void)ecpair::sequencer::SdoInformationClient(transport, clock).entry_description(0x1018, 1, timeout); break;
        case 3: (void)ecpair::sequencer::FoeClient(transport, clock).read("fw", 0, 4096, timeout); break;
        case 4: (void)ecpair::sequencer::FoeClient(transport, clock).write("fw", 7, std::vector<std::uint8_t>(300, 1), timeout); break;
        case 5: (void)ecpair::sequencer::SoeClient(transport, clock).read(0, 15, 0x40, timeout); break;
        case 6: (void)ecpair::sequencer::SoeClient(transport, clock).write(1, 16, 0x40, std::vector<std::uint8_t>(300, 2), timeout); break;
        default: (void)ecpair::sequencer::EoeClient(transport, clock).set_ip_parameters(ecpair::wire::EoeIpParameters{}, 0, timeout); break;
    }
    return 0;
}
