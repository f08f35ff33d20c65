#pragma once
// What the master knows of each configured slave (ENI order): present or
// absent, its last AL status and status code, its station address. The
// state machine and the slave monitor write it, the operator API and the
// redundancy (CMF, mirror) read it. Updates and snapshots are briefly locked.

#include <cstdint>
#include <mutex>
#include <vector>

namespace ecpair::master {

// What Hot-Connect knows of a slave beyond "it answers" (SlaveStateEntry::hot_connect).
inline constexpr std::uint8_t kGroupPresent = 0x01;   // its group is identified and part of the bus
inline constexpr std::uint8_t kJoining = 0x02;        // being brought to the master state by a topology change
inline constexpr std::uint8_t kAwaitingAccept = 0x04; // found, waiting for the operator's accept (manual modes)
inline constexpr std::uint8_t kRefused = 0x08;        // found but not as configured: left out
inline constexpr std::uint8_t kHotConnectFlags = 0x0F;

struct SlaveStateEntry {
    bool present = false;
    std::uint8_t al_status = 0;        // 0x0130 low byte: state bits + error flag (0 = not read yet)
    std::uint16_t al_status_code = 0;  // 0x0134
    std::uint16_t station_address = 0;
    std::uint8_t hot_connect = 0;      // kGroupPresent | kJoining | kAwaitingAccept | kRefused
    friend bool operator==(const SlaveStateEntry&, const SlaveStateEntry&) = default;
};

class SlaveStateImage {
public:
    explicit SlaveStateImage(std::size_t slaves) : entries_(slaves) {}

    std::size_t size() const { return entries_.size(); }
    std::vector<SlaveStateEntry> snapshot() const {
        std::lock_guard lock(mutex_);
        return entries_;
    }
    // Copies into `out` (no allocation once `out` has the size).
    void copy_to(std::vector<SlaveStateEntry>& out) const {
        std::lock_guard lock(mutex_);
        out.assign(entries_.begin(), entries_.end());
    }
    SlaveStateEntry get(std::size_t index) const {
        std::lock_guard lock(mutex_);
        return entries_[index];
    }
    // Returns the previous entry.
    SlaveStateEntry set(std::size_t index, const SlaveStateEntry& entry) {
        std::lock_guard lock(mutex_);
        const auto previous = entries_[index];
        entries_[index] = entry;
        return previous;
    }
    // What the slave monitor read (presence, AL status): keeps the Hot-Connect flags.
    SlaveStateEntry set_observed(std::size_t index, const SlaveStateEntry& observed) {
        std::lock_guard lock(mutex_);
        const auto previous = entries_[index];
        entries_[index] = observed;
        entries_[index].hot_connect = previous.hot_connect;
        return previous;
    }
    // Hot-Connect's view of a slave: its flags, and whether it is present.
    void set_hot_connect(std::size_t index, std::uint8_t flags, bool present) {
        std::lock_guard lock(mutex_);
        entries_[index].hot_connect = flags;
        entries_[index].present = present;
    }
    void assign(const std::vector<SlaveStateEntry>& entries) {
        std::lock_guard lock(mutex_);
        entries_.assign(entries.begin(), entries.end());
    }

private:
    mutable std::mutex mutex_;
    std::vector<SlaveStateEntry> entries_;
};

}  // namespace ecpair::master
