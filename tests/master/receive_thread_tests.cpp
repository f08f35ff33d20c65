// The receive thread's modes: READING hands every frame over at once; once
// PARKED it leaves the link alone and drain_link, on the caller's thread,
// takes what waits (with when it arrived); resume() hands frames over again.
// Frames cross a MemoryWire; waits are bounded polls, never timing thresholds.

#include <atomic>
#include <chrono>
#include <mutex>
#include <thread>
#include <vector>

#include <catch2/catch.hpp>

#include "ecpair/link/memory_link.hpp"
#include "ecpair/master/link_drain.hpp"
#include "ecpair/master/receive_thread.hpp"

using namespace ecpair;
using namespace std::chrono_literals;

namespace {

wire::MacAddress mac(std::uint8_t last) { return {{0x02, 0x00, 0x00, 0x00, 0x00, last}}; }

// A frame whose first byte says which it is.
std::vector<std::uint8_t> numbered(std::uint8_t n) {
    std::vector<std::uint8_t> frame(60, 0);
    frame[0] = n;
    return frame;
}

class Received {
public:
    void add(ConstBytes frame) {
        std::lock_guard lock(mutex_);
        numbers_.push_back(frame[0]);
    }
    std::vector<std::uint8_t> numbers() const {
        std::lock_guard lock(mutex_);
        return numbers_;
    }

private:
    mutable std::mutex mutex_;
    std::vector<std::uint8_t> numbers_;
};

template <class Condition>
bool eventually(Condition condition) {
    for (int i = 0; i < 500; ++i) {
        if (condition()) return true;
        std::this_thread::sleep_for(2ms);
    }
    return condition();
}

}  // namespace

TEST_CASE("a parked receive thread leaves the link's frames to drain_link, and takes them again after resume()",
          "[master][receive]") {
    auto ends = link::MemoryWire::make_pair("sender", mac(1), "receiver", mac(2));
    Received by_thread;
    master::ReceiveThread rx(*ends.b, [&](ConstBytes frame, link::Clock::time_point) { by_thread.add(frame); },
                             "test-rx");
    rx.start();
    CHECK(rx.mode() == master::ReceiveMode::Reading);

    REQUIRE(ends.a->send(numbered(1)));
    REQUIRE(eventually([&] { return by_thread.numbers().size() == 1; }));

    rx.pause();
    REQUIRE(eventually([&] { return rx.parked(); }));
    const auto sent_at = link::Clock::now();
    REQUIRE(ends.a->send(numbered(2)));
    REQUIRE(ends.a->send(numbered(3)));
    std::this_thread::sleep_for(50ms);  // time the thread would have taken them in
    CHECK(by_thread.numbers() == std::vector<std::uint8_t>{1});

    std::array<std::uint8_t, 2048> buffer{};
    std::vector<std::uint8_t> drained;
    std::vector<link::Clock::time_point> arrivals;
    const auto drained_at = link::Clock::now();
    const auto taken = master::drain_link(*ends.b, buffer, 16, [&](ConstBytes frame, link::Clock::time_point at) {
        drained.push_back(frame[0]);
        arrivals.push_back(at);
    });
    CHECK(taken == 2);
    CHECK(drained == std::vector<std::uint8_t>{2, 3});
    for (const auto at : arrivals) {
        // When they arrived (sent 50 ms before the drain), not when they were read.
        CHECK(at >= sent_at - 5ms);
        CHECK(at < drained_at - 25ms);
    }

    rx.resume();
    CHECK_FALSE(rx.parked());
    REQUIRE(ends.a->send(numbered(4)));
    REQUIRE(eventually([&] { return by_thread.numbers().size() == 2; }));
    CHECK(by_thread.numbers() == std::vector<std::uint8_t>{1, 4});
    rx.stop();
}

TEST_CASE("drain_link takes at most its limit, the rest waits for the next call", "[master][receive]") {
    auto ends = link::MemoryWire::make_pair("sender", mac(1), "receiver", mac(2));
    for (std::uint8_t n = 1; n <= 5; ++n) REQUIRE(ends.a->send(numbered(n)));
    std::array<std::uint8_t, 2048> buffer{};
    std::vector<std::uint8_t> got;
    const auto record = [&](ConstBytes frame, link::Clock::time_point) { got.push_back(frame[0]); };
    CHECK(master::drain_link(*ends.b, buffer, 3, record) == 3);
    CHECK(master::drain_link(*ends.b, buffer, 3, record) == 2);
    CHECK(master::drain_link(*ends.b, buffer, 3, record) == 0);
    CHECK(got == std::vector<std::uint8_t>{1, 2, 3, 4, 5});
}

TEST_CASE("a receive thread paused before it ran parks, resumed while parking never parks, and stops while parked",
          "[master][receive]") {
    auto ends = link::MemoryWire::make_pair("sender", mac(1), "receiver", mac(2));
    std::atomic<int> frames{0};
    master::ReceiveThread rx(*ends.b, [&](ConstBytes, link::Clock::time_point) { ++frames; }, "test-rx");
    rx.pause();  // before start: it parks at once
    rx.start();
    REQUIRE(eventually([&] { return rx.parked(); }));
    REQUIRE(ends.a->send(numbered(1)));
    std::this_thread::sleep_for(20ms);
    CHECK(frames.load() == 0);

    rx.resume();
    rx.pause();
    rx.resume();  // PARKING -> READING: the thread goes on reading
    REQUIRE(eventually([&] { return frames.load() == 1; }));
    CHECK(rx.mode() == master::ReceiveMode::Reading);

    rx.pause();
    REQUIRE(eventually([&] { return rx.parked(); }));
    rx.stop();  // returns: a parked thread still hears stop()
    CHECK(rx.parked());
}
