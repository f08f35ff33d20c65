#pragma once
// An in-memory Ethernet cable for unit tests and in-process simulations.
//
//   auto [wire, a, b] = MemoryWire::make_pair("main0", mac_a, "sim0", mac_b);
//
// What `a` sends, `b` receives and the other way round, in order. Each
// direction has a bounded queue; a frame sent into a full queue is dropped
// and counted. Each end's selectable fd is an eventfd that is readable while
// frames wait, so the ends work with poll/asio exactly like a PcapLink.
//
// wire->set_link_up(false) pulls the cable: link_up() turns false on both
// ends, frames sent meanwhile are dropped (and counted; send() still
// succeeds, as it would on a NIC with no carrier), frames already queued stay
// receivable, and every watcher from wire->watch() reports the change.
//
// Each end is safe for one sending thread and one receiving thread. Nothing
// is allocated per frame: the queues are rings of preallocated slots.
// Creating a wire throws std::system_error if no eventfd can be made.

#include <atomic>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "ecpair/link/link.hpp"
#include "ecpair/link/link_state_source.hpp"

namespace ecpair::link {

namespace detail {
class FrameQueue;
class MemoryWireWatcher;
}  // namespace detail

struct MemoryWireOptions {
    std::size_t queue_capacity = 64;  // frames waiting per direction
};

class MemoryWire;

class MemoryLink final : public Link {
public:
    // What this end sent: delivered to the peer's queue, or dropped.
    struct Counters {
        std::uint64_t delivered = 0;
        std::uint64_t dropped_queue_full = 0;
        std::uint64_t dropped_link_down = 0;
        std::uint64_t batches = 0;  // send_batch calls that carried at least one frame
    };

    ~MemoryLink() override;

    const std::string& name() const override { return name_; }
    wire::MacAddress mac() const override { return mac_; }
    Expected<void, LinkError> send(ConstBytes frame) override;
    // Each frame as send() would; counted as one batch (Counters::batches).
    BatchSendResult send_batch(std::span<const ConstBytes> frames) override;
    Expected<std::optional<ReceivedFrame>, LinkError> try_receive(Bytes buffer) override;
    Expected<std::optional<ReceivedFrame>, LinkError> receive(Bytes buffer, std::chrono::nanoseconds timeout) override;
    int selectable_fd() const override;
    bool link_up() const override;

    Counters counters() const;

private:
    friend class MemoryWire;
    MemoryLink(std::shared_ptr<MemoryWire> shared_wire, std::string name, wire::MacAddress mac,
               detail::FrameQueue& inbound, detail::FrameQueue& outbound);

    std::shared_ptr<MemoryWire> wire_;
    std::string name_;
    wire::MacAddress mac_;
    detail::FrameQueue& inbound_;
    detail::FrameQueue& outbound_;
    std::atomic<std::uint64_t> delivered_{0};
    std::atomic<std::uint64_t> dropped_queue_full_{0};
    std::atomic<std::uint64_t> dropped_link_down_{0};
    std::atomic<std::uint64_t> batches_{0};
};

class MemoryWire : public std::enable_shared_from_this<MemoryWire> {
public:
    struct Ends {
        std::shared_ptr<MemoryWire> wire;
        std::unique_ptr<MemoryLink> a;
        std::unique_ptr<MemoryLink> b;
    };

    static Ends make_pair(std::string name_a, wire::MacAddress mac_a, std::string name_b, wire::MacAddress mac_b,
                          const MemoryWireOptions& options = {});

    ~MemoryWire();
    MemoryWire(const MemoryWire&) = delete;
    MemoryWire& operator=(const MemoryWire&) = delete;

    // Plugs (true) or pulls (false) the cable. Setting the current state
    // again changes nothing and reports nothing.
    void set_link_up(bool up);
    bool link_up() const { return up_.load(); }

    // A LinkStateSource reporting this wire's changes under both end names.
    // It may outlive the wire's ends.
    std::unique_ptr<LinkStateSource> watch();

private:
    friend class MemoryLink;
    friend class detail::MemoryWireWatcher;
    MemoryWire(std::string name_a, std::string name_b, const MemoryWireOptions& options);

    void remove_watcher(detail::MemoryWireWatcher* watcher);

    const std::string name_a_;
    const std::string name_b_;
    std::unique_ptr<detail::FrameQueue> a_to_b_;
    std::unique_ptr<detail::FrameQueue> b_to_a_;
    std::atomic<bool> up_{true};
    std::mutex watchers_mutex_;  // guards watchers_ and orders state reports
    std::vector<detail::MemoryWireWatcher*> watchers_;
};

}  // namespace ecpair::link
