// Same eventfd discipline as FrameQueue: written when the first change is
// queued, drained when read_changes() empties the queue.

#include "memory_wire_watcher.hpp"

#include <sys/eventfd.h>
#include <unistd.h>

#include <cerrno>
#include <system_error>

#include "ecpair/link/memory_link.hpp"

namespace ecpair::link::detail {

MemoryWireWatcher::MemoryWireWatcher(std::shared_ptr<MemoryWire> wire)
    : wire_(std::move(wire)), event_(::eventfd(0, EFD_NONBLOCK | EFD_CLOEXEC)) {
    if (!event_.valid()) throw std::system_error(errno, std::system_category(), "eventfd for a memory wire watcher");
}

MemoryWireWatcher::~MemoryWireWatcher() { wire_->remove_watcher(this); }

void MemoryWireWatcher::report(const LinkStateChange& change) {
    std::lock_guard lock(mutex_);
    pending_.push_back(change);
    if (pending_.size() == 1) {
        const std::uint64_t one = 1;
        [[maybe_unused]] const auto written = ::write(event_.get(), &one, sizeof(one));
    }
}

std::vector<LinkStateChange> MemoryWireWatcher::read_changes() {
    std::lock_guard lock(mutex_);
    if (pending_.empty()) return {};
    std::uint64_t drained = 0;
    [[maybe_unused]] const auto read = ::read(event_.get(), &drained, sizeof(drained));
    return std::exchange(pending_, {});
}

std::optional<bool> MemoryWireWatcher::is_up(const std::string& interface) const {
    if (interface != wire_->name_a_ && interface != wire_->name_b_) return std::nullopt;
    return wire_->link_up();
}

}  // namespace ecpair::link::detail
