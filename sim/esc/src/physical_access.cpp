// An access is cut into its register part, its RAM part and whatever lies
// beyond the RAM; the RAM part is copied around the ranges the SyncManagers
// refuse. The common cases (a register read, a process data copy through a
// buffered SyncManager) are a single memcpy.

#include "physical_access.hpp"

#include <algorithm>

#include "ecpair/wire/esc_registers.hpp"
#include "register_map.hpp"

namespace ecpair::sim {
namespace {

namespace reg = wire::reg;

void transfer_in(Bytes out, ConstBytes source, ReadMode mode) {
    if (mode == ReadMode::Copy) {
        std::copy(source.begin(), source.end(), out.begin());
    } else {
        for (std::size_t i = 0; i < source.size(); ++i) out[i] = static_cast<std::uint8_t>(out[i] | source[i]);
    }
}

// Calls `transfer(begin, end)` for every piece of [begin, end) the plan does not refuse.
template <class Transfer>
void for_each_permitted(const SmAccessPlan& plan, std::uint32_t begin, std::uint32_t end, Transfer&& transfer) {
    std::uint32_t cursor = begin;
    for (std::size_t i = 0; i < plan.refused_count; ++i) {
        const auto& refused = plan.refused[i];
        if (refused.begin > cursor) transfer(cursor, std::min(refused.begin, end));
        cursor = std::max(cursor, refused.end);
    }
    if (cursor < end) transfer(cursor, end);
}

}  // namespace

PhysicalAccess::PhysicalAccess(EscMemory& memory, SyncManagerUnit& sync_managers)
    : memory_(memory), sync_managers_(sync_managers) {}

std::uint32_t PhysicalAccess::ram_end() const {
    return process_ram_available_ ? memory_.ram_end() : regs::kProcessRam;
}

bool PhysicalAccess::read(std::uint32_t address, Bytes out, ReadMode mode) {
    if (out.empty()) return false;
    const std::uint64_t end = std::uint64_t{address} + out.size();
    bool any = false;
    if (address < regs::kShadowedEnd) {
        const auto register_end = static_cast<std::uint32_t>(std::min<std::uint64_t>(end, regs::kShadowedEnd));
        read_registers(address, out.first(register_end - address), mode);
        any = true;
    }
    const std::uint32_t ram_begin = std::max<std::uint32_t>(address, regs::kUserRam);
    const auto ram_stop = static_cast<std::uint32_t>(std::min<std::uint64_t>(end, ram_end()));
    if (ram_begin < ram_stop) {
        any = read_ram(ram_begin, out.subspan(ram_begin - address, ram_stop - ram_begin), mode) || any;
    }
    return any;
}

bool PhysicalAccess::write(std::uint32_t address, ConstBytes in) {
    if (in.empty()) return false;
    const std::uint64_t end = std::uint64_t{address} + in.size();
    bool any = false;
    if (address < regs::kShadowedEnd) {
        const auto register_end = static_cast<std::uint32_t>(std::min<std::uint64_t>(end, regs::kShadowedEnd));
        memory_.stage(static_cast<std::uint16_t>(address), in.first(register_end - address));
        sync_managers_.note_register_write(address, register_end - address);
        any = true;
    }
    const std::uint32_t ram_begin = std::max<std::uint32_t>(address, regs::kUserRam);
    const auto ram_stop = static_cast<std::uint32_t>(std::min<std::uint64_t>(end, ram_end()));
    if (ram_begin < ram_stop) {
        any = write_ram(ram_begin, in.subspan(ram_begin - address, ram_stop - ram_begin)) || any;
    }
    return any;
}

void PhysicalAccess::read_registers(std::uint32_t address, Bytes out, ReadMode mode) {
    const auto end = static_cast<std::uint32_t>(address + out.size());
    if (computed_ != nullptr && regs::overlaps(address, end, reg::kDcSystemTime, reg::kDcCycleTime0)) {
        computed_->before_read(address, end);
    }
    transfer_in(out, memory_.bytes().subspan(address, out.size()), mode);
    // Reading DL status / AL status acknowledges their ECAT events.
    std::uint16_t cleared = 0;
    if (regs::overlaps(address, end, reg::kDlStatus, reg::kDlStatus + 2)) cleared |= regs::kEventDlStatus;
    if (regs::overlaps(address, end, reg::kAlStatus, reg::kAlStatus + 2)) cleared |= regs::kEventAlStatus;
    if (cleared != 0) {
        const auto request = memory_.load<std::uint16_t>(reg::kEcatEventRequest);
        memory_.store<std::uint16_t>(reg::kEcatEventRequest, static_cast<std::uint16_t>(request & ~cleared));
    }
}

bool PhysicalAccess::read_ram(std::uint32_t address, Bytes out, ReadMode mode) {
    const auto end = static_cast<std::uint32_t>(address + out.size());
    const SmAccessPlan plan = sync_managers_.plan_ecat_access(address, out.size(), false);
    if (!plan.any_permitted) return false;
    for_each_permitted(plan, address, end, [&](std::uint32_t begin, std::uint32_t stop) {
        transfer_in(out.subspan(begin - address, stop - begin), memory_.bytes().subspan(begin, stop - begin), mode);
    });
    return true;
}

bool PhysicalAccess::write_ram(std::uint32_t address, ConstBytes in) {
    const auto end = static_cast<std::uint32_t>(address + in.size());
    const SmAccessPlan plan = sync_managers_.plan_ecat_access(address, in.size(), true);
    if (!plan.any_permitted) return false;
    Bytes memory = memory_.bytes();
    for_each_permitted(plan, address, end, [&](std::uint32_t begin, std::uint32_t stop) {
        const auto piece = in.subspan(begin - address, stop - begin);
        std::copy(piece.begin(), piece.end(), memory.begin() + begin);
    });
    return true;
}

}  // namespace ecpair::sim
