#pragma once
// The LinkStateSource of a MemoryWire: the wire pushes each state change to
// every registered watcher, which queues it and signals its eventfd.

#include <memory>
#include <mutex>
#include <vector>

#include "ecpair/link/link_state_source.hpp"
#include "unique_fd.hpp"

namespace ecpair::link {
class MemoryWire;
}

namespace ecpair::link::detail {

class MemoryWireWatcher final : public LinkStateSource {
public:
    // Does not register itself: MemoryWire::watch() does.
    explicit MemoryWireWatcher(std::shared_ptr<MemoryWire> wire);
    ~MemoryWireWatcher() override;

    int selectable_fd() const override { return event_.get(); }
    std::vector<LinkStateChange> read_changes() override;
    std::optional<bool> is_up(const std::string& interface) const override;

    // Called by the wire (under its watcher lock) for each change.
    void report(const LinkStateChange& change);

private:
    std::shared_ptr<MemoryWire> wire_;
    std::mutex mutex_;
    std::vector<LinkStateChange> pending_;
    UniqueFd event_;
};

}  // namespace ecpair::link::detail
