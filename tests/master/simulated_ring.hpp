#pragma once
// An in-process ring for master tests: the master's MAIN and RED links are
// MemoryLinks whose far ends feed an ecsim Segment on a thread of its own,
// the way ecsim does it on real interfaces. Faults go through with_segment().

#include <poll.h>
#include <sys/eventfd.h>
#include <unistd.h>

#include <array>
#include <atomic>
#include <mutex>
#include <thread>

#include "ecpair/eni/model.hpp"
#include "ecpair/link/memory_link.hpp"
#include "ecpair/sim/segment.hpp"

namespace ecpair::test {

class SimulatedRing {
public:
    explicit SimulatedRing(const eni::EniConfig& eni)
        : segment_(std::move(sim::Segment::from_eni(eni).value())),
          main_(link::MemoryWire::make_pair("m-main", mac(0x11), "sim-main", mac(0x21))),
          red_(link::MemoryWire::make_pair("m-red", mac(0x12), "sim-red", mac(0x22))),
          stop_fd_(eventfd(0, EFD_CLOEXEC)) {
        thread_ = std::thread([this] { run(); });
    }
    ~SimulatedRing() {
        const std::uint64_t one = 1;
        [[maybe_unused]] auto n = write(stop_fd_, &one, sizeof one);
        thread_.join();
        close(stop_fd_);
    }

    link::Link& main() { return *main_.a; }
    link::Link& red() { return *red_.a; }
    link::MemoryWire& main_cable() { return *main_.wire; }
    link::MemoryWire& red_cable() { return *red_.wire; }

    template <class F>
    auto with_segment(F&& f) {
        std::lock_guard lock(mutex_);
        return f(segment_);
    }

private:
    static wire::MacAddress mac(std::uint8_t last) { return {{0x02, 0x00, 0x00, 0x00, 0x00, last}}; }

    void run() {
        std::array<std::uint8_t, 1600> buffer{};
        link::Link* sides[2] = {main_.b.get(), red_.b.get()};
        std::array<pollfd, 3> fds{pollfd{sides[0]->selectable_fd(), POLLIN, 0},
                                  pollfd{sides[1]->selectable_fd(), POLLIN, 0}, pollfd{stop_fd_, POLLIN, 0}};
        for (;;) {
            if (poll(fds.data(), fds.size(), -1) < 0) continue;
            if (fds[2].revents != 0) return;
            for (int s = 0; s < 2; ++s) {
                for (;;) {
                    auto frame = sides[s]->try_receive(buffer);
                    if (!frame || !frame->has_value()) break;
                    std::size_t size = (*frame)->size;
                    std::lock_guard lock(mutex_);
                    segment_.set_side_link(sim::Side::Main, main_.wire->link_up());
                    segment_.set_side_link(sim::Side::Red, red_.wire->link_up());
                    const auto exit = segment_.carry(static_cast<sim::Side>(s), buffer, size, now_ns());
                    if (exit) (void)sides[static_cast<int>(*exit)]->send(std::span<const std::uint8_t>(buffer.data(), size));
                }
            }
        }
    }

    static std::uint64_t now_ns() {
        return static_cast<std::uint64_t>(std::chrono::duration_cast<std::chrono::nanoseconds>(
                                              std::chrono::steady_clock::now().time_since_epoch())
                                              .count());
    }

    std::mutex mutex_;
    sim::Segment segment_;
    link::MemoryWire::Ends main_;
    link::MemoryWire::Ends red_;
    int stop_fd_;
    std::thread thread_;
};

}  // namespace ecpair::test
