#include "demo_application.hpp"

#include <algorithm>

#include <fmt/format.h>

#include "ecpair/common/hex.hpp"
#include "ecpair/common/log.hpp"

namespace ecpair::daemon {
namespace {

constexpr std::uint32_t kCounterBytes = 2;  // ecsim's slaves put a counter first
constexpr std::uint64_t kMismatchesLogged = 10;  // then only the counter grows

}  // namespace

DemoApplication::DemoApplication(const eni::EniConfig& eni, config::DemoKind kind, std::uint32_t step_cycles)
    : kind_(kind), step_cycles_(std::max<std::uint32_t>(step_cycles, 1)) {
    for (const auto& slave : eni.slaves) {
        const auto& send = slave.process_data.send;
        const auto& recv = slave.process_data.recv;
        if (!send || send->bit_length < 8 || send->bit_start % 8 != 0) continue;
        outputs_.push_back({send->bit_start / 8, send->bit_length / 8});
        if (recv && recv->bit_start % 8 == 0 && recv->bit_length / 8 > kCounterBytes) {
            const std::uint32_t length = std::min(send->bit_length / 8, recv->bit_length / 8 - kCounterBytes);
            checks_.push_back({send->bit_start / 8, recv->bit_start / 8 + kCounterBytes, length,
                               fmt::format("\"{}\" (station {})", slave.info.name, slave.info.phys_addr)});
        }
    }
}

void DemoApplication::write_outputs(master::ProcessImage& image, std::uint64_t cycle) {
    auto outputs = image.outputs();
    const auto step = cycle / step_cycles_;
    for (const auto& area : outputs_) {
        for (std::uint32_t i = 0; i < area.output_length && area.output_offset + i < outputs.size(); ++i) {
            outputs[area.output_offset + i] = static_cast<std::uint8_t>(1u << ((step + i) % 8));
        }
    }
}

bool DemoApplication::matches(const master::ProcessImage& image, const LoopbackCheck& check,
                              ConstBytes outputs) const {
    const auto inputs = image.inputs();
    if (check.input_offset + check.length > inputs.size() || check.output_offset + check.length > outputs.size()) {
        return false;
    }
    return std::equal(outputs.begin() + check.output_offset, outputs.begin() + check.output_offset + check.length,
                      inputs.begin() + check.input_offset);
}

LoopbackStats DemoApplication::stats() const {
    return LoopbackStats{stats_.cycles_checked.load(std::memory_order_relaxed),
                         stats_.mismatches.load(std::memory_order_relaxed),
                         stats_.slaves_checked.load(std::memory_order_relaxed)};
}

void DemoApplication::report_mismatch(const master::ProcessImage& image, const LoopbackCheck& check,
                                      std::uint64_t cycle) const {
    const auto mismatches = stats_.mismatches.load(std::memory_order_relaxed);
    if (mismatches > kMismatchesLogged) return;
    const auto inputs = image.inputs();
    const auto outputs = image.outputs();
    const auto bytes = [&](ConstBytes area, std::uint32_t offset) {
        return offset + check.length <= area.size() ? to_hex(area.subspan(offset, check.length)) : std::string("?");
    };
    logger("demo")->warn("loopback check, cycle {}: slave {} echoed {}, but the outputs were {} in this cycle and {} "
                         "in the one before (both cycles came back complete){}",
                         cycle, check.slave, bytes(inputs, check.input_offset), bytes(outputs, check.output_offset),
                         bytes(previous_outputs_, check.output_offset),
                         mismatches == kMismatchesLogged ? "; further mismatches are only counted" : "");
}

void DemoApplication::on_cycle(master::ProcessImage& image, const master::CycleInfo& info) {
    if (kind_ == config::DemoKind::None) return;
    // A passive (INACTIVE) master mirrors the partner's image: nothing to write or check, and
    // once it sends again, what it remembers from before is no guide to what the slaves hold.
    if (!info.sending) {
        previous_inputs_valid_ = false;
        previous_outputs_.clear();
        return;
    }
    // The inputs of this cycle answer the outputs of the previous one(s): check first, then write new outputs.
    if (kind_ == config::DemoKind::LoopbackCheck && info.state == eni::SlaveState::Op && info.inputs_valid &&
        previous_inputs_valid_ && !previous_outputs_.empty()) {
        stats_.cycles_checked.fetch_add(1, std::memory_order_relaxed);
        for (const auto& check : checks_) {
            stats_.slaves_checked.fetch_add(1, std::memory_order_relaxed);
            if (!matches(image, check, image.outputs()) && !matches(image, check, previous_outputs_)) {
                stats_.mismatches.fetch_add(1, std::memory_order_relaxed);
                report_mismatch(image, check, info.cycle);
            }
        }
    }
    previous_inputs_valid_ = info.inputs_valid;
    previous_outputs_.assign(image.outputs().begin(), image.outputs().end());
    write_outputs(image, info.cycle);
}

}  // namespace ecpair::daemon
