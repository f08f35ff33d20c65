#pragma once
// Something that reports link up/down changes as they happen, with a file
// descriptor to wait on. Two implementations:
//   - LinkStateMonitor (link_state_monitor.hpp): kernel interfaces, netlink;
//   - the watcher of a MemoryWire (memory_link.hpp): pulling the in-memory cable.
// Code that reacts to link loss (the redundancy logic) takes a
// LinkStateSource and works the same on both. A source is read from one
// thread (it may be another than the one that opened it).

#include <optional>
#include <string>
#include <vector>

#include "ecpair/link/link.hpp"

namespace ecpair::link {

struct LinkStateChange {
    std::string interface;  // the link's name()
    bool up = false;        // carrier and operational state: frames can flow
    Clock::time_point timestamp;  // when the change was seen
};

class LinkStateSource {
public:
    virtual ~LinkStateSource() = default;
    LinkStateSource() = default;
    LinkStateSource(const LinkStateSource&) = delete;
    LinkStateSource& operator=(const LinkStateSource&) = delete;

    // Readable when read_changes() may have something (for poll/epoll/asio).
    virtual int selectable_fd() const = 0;

    // Non-blocking: every change seen since the last call, oldest first;
    // empty when nothing changed.
    virtual std::vector<LinkStateChange> read_changes() = 0;

    // The last known state of a watched interface; nullopt when the source
    // does not watch it or it does not exist.
    virtual std::optional<bool> is_up(const std::string& interface) const = 0;
};

}  // namespace ecpair::link
