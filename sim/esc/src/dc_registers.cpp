// The unit reads the master's staged bytes of 0x0910 directly (their mask is
// 0, so the commit never stores them) and writes its results into the
// register file.

#include "dc_registers.hpp"

#include <algorithm>
#include <cstdlib>

#include "ecpair/wire/esc_registers.hpp"

namespace ecpair::sim {
namespace {

namespace reg = wire::reg;

constexpr std::uint32_t kSignBit = 0x80000000U;
constexpr std::uint64_t kMagnitudeMax = 0x7FFFFFFFU;

}  // namespace

DcUnit::DcUnit(EscMemory& memory) : memory_(memory) {}

void DcUnit::reset() {
    arrivals_ = {};
    latch_pending_ = false;
    latch_seq_ = 0;
}

void DcUnit::start_of_frame(std::uint64_t time_ns) {
    memory_.store<std::uint64_t>(reg::kDcSystemTime, time_ns + memory_.load<std::uint64_t>(reg::kDcSystemTimeOffset));
}

void DcUnit::port_arrival(int port, std::uint64_t time_ns, std::uint64_t frame_seq) {
    arrivals_[static_cast<std::size_t>(port)] = Arrival{time_ns, frame_seq, true};
    if (latch_pending_ && frame_seq == latch_seq_ && port != 0) latch_port(port, time_ns);
}

void DcUnit::latch_receive_times(std::uint64_t frame_seq, std::uint64_t epu_time_ns) {
    latch_pending_ = true;
    latch_seq_ = frame_seq;
    const Arrival& port0 = arrivals_[0];
    latch_port(0, port0.valid && port0.frame_seq == frame_seq ? port0.time_ns : epu_time_ns);
    memory_.store<std::uint64_t>(reg::kDcReceiveTimeEcu, epu_time_ns);
    for (int p = 1; p < kMaxPorts; ++p) {
        const Arrival& a = arrivals_[static_cast<std::size_t>(p)];
        if (a.valid && a.frame_seq == frame_seq) latch_port(p, a.time_ns);
    }
}

void DcUnit::system_time_written(std::uint64_t time_ns) {
    std::uint64_t written = 0;
    unsigned width = 0;
    for (unsigned i = 0; i < 8; ++i) {
        const auto address = static_cast<std::uint16_t>(reg::kDcSystemTime + i);
        if (!memory_.staged(address)) continue;
        written |= std::uint64_t{memory_.staged_value(address)} << (8 * i);
        width = i + 1;
    }
    if (width == 0) return;
    const std::uint64_t local = time_ns + memory_.load<std::uint64_t>(reg::kDcSystemTimeOffset);
    const std::uint64_t received = written + memory_.load<std::uint32_t>(reg::kDcSystemTimeDelay);
    const std::int64_t difference = width > 4 ? static_cast<std::int64_t>(local - received)
                                              : static_cast<std::int32_t>(static_cast<std::uint32_t>(local) -
                                                                          static_cast<std::uint32_t>(received));
    const std::uint64_t magnitude =
        std::min<std::uint64_t>(difference < 0 ? 0 - static_cast<std::uint64_t>(difference) : static_cast<std::uint64_t>(difference),
                                kMagnitudeMax);
    const auto value = static_cast<std::uint32_t>(magnitude | (difference < 0 ? kSignBit : 0U));
    memory_.store<std::uint32_t>(reg::kDcSystemTimeDifference, value);
}

void DcUnit::latch_port(int port, std::uint64_t time_ns) {
    memory_.store<std::uint32_t>(static_cast<std::uint16_t>(reg::kDcReceiveTimes + 4 * port),
                                 static_cast<std::uint32_t>(time_ns));
}

}  // namespace ecpair::sim
