// Writes straight into the input buffer (the PDI side of a buffered
// SyncManager), so the master reads it with its next LRD/LRW; a mailbox-mode
// buffer is filled only when empty and then marked full (the PDI's write of
// its last byte), a mailbox-mode output buffer emptied once read.

#include "slave_application.hpp"

#include <algorithm>

namespace ecpair::sim {
namespace {

constexpr std::size_t kCounterBytes = 2;

}  // namespace

SlaveApplication::SlaveApplication(EscMemory& memory, SyncManagerUnit& sync_managers, const EscLayout& layout)
    : memory_(memory), sync_managers_(sync_managers), output_sm_(layout.output_sm), input_sm_(layout.input_sm) {}

bool SlaveApplication::usable(const SmChannel& channel, bool ecat_writes) const {
    return channel.active() && !channel.pdi_deactivated && channel.ecat_writes() == ecat_writes &&
           channel.start >= regs::kProcessRam && channel.end() <= memory_.ram_end();
}

void SlaveApplication::after_frame(AlState state) {
    if (state != AlState::Safeop && state != AlState::Op) return;
    const SmChannel& out = sync_managers_.channel(output_sm_);
    const bool outputs_usable = usable(out, true);
    // A single-buffered output SyncManager the master filled: taken (the data stays in RAM), empty for the next write.
    if (outputs_usable && out.mailbox() && sync_managers_.mailbox_full(output_sm_)) {
        sync_managers_.pdi_mailbox_consumed(output_sm_);
    }
    const SmChannel& in = sync_managers_.channel(input_sm_);
    if (!usable(in, false)) return;
    // A single-buffered input SyncManager the master has not read yet keeps what it holds.
    if (in.mailbox() && sync_managers_.mailbox_full(input_sm_)) return;
    Bytes inputs = memory_.bytes().subspan(in.start, in.length);
    ++counter_;
    std::size_t mirror_at = 0;
    if (inputs.size() >= kCounterBytes) {
        store_le<std::uint16_t>(inputs, 0, counter_);
        mirror_at = kCounterBytes;
    }
    Bytes mirror = inputs.subspan(mirror_at);
    std::size_t copied = 0;
    if (state == AlState::Op && outputs_usable) {
        copied = std::min<std::size_t>(out.length, mirror.size());
        const ConstBytes outputs = ConstBytes(memory_.bytes()).subspan(out.start, copied);
        std::copy(outputs.begin(), outputs.end(), mirror.begin());
    }
    std::fill(mirror.begin() + static_cast<std::ptrdiff_t>(copied), mirror.end(), std::uint8_t{0});
    if (word_address_ >= in.start && word_address_ + 2u <= in.end()) {
        store_le<std::uint16_t>(inputs, word_address_ - in.start, word_value_);
    }
    if (in.mailbox()) sync_managers_.pdi_mailbox_filled(input_sm_);
}

}  // namespace ecpair::sim
