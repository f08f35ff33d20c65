// MemoryWire / MemoryLink: delivery, order, overflow and cable-pull counting,
// the eventfd contract (readable exactly while frames wait), blocking
// receives, and the state watcher.

#include <poll.h>

#include <catch2/catch.hpp>
#include <numeric>
#include <thread>
#include <vector>

#include "ecpair/link/memory_link.hpp"
#include "ecpair/wire/constants.hpp"

using namespace std::chrono_literals;
using ecpair::link::LinkErrc;
using ecpair::link::MemoryWire;
using ecpair::link::MemoryWireOptions;
using ecpair::wire::MacAddress;

namespace {

const MacAddress kMacA{{0x02, 0, 0, 0, 0, 0x0a}};
const MacAddress kMacB{{0x02, 0, 0, 0, 0, 0x0b}};

std::vector<std::uint8_t> make_frame(std::size_t size, std::uint8_t seed) {
    std::vector<std::uint8_t> frame(size);
    std::iota(frame.begin(), frame.end(), seed);
    return frame;
}

bool readable(int fd) {
    pollfd entry{fd, POLLIN, 0};
    return ::poll(&entry, 1, 0) == 1 && (entry.revents & POLLIN) != 0;
}

MemoryWire::Ends make_wire(std::size_t capacity = 64) {
    return MemoryWire::make_pair("a0", kMacA, "b0", kMacB, MemoryWireOptions{capacity});
}

}  // namespace

TEST_CASE("memory link: each end has its name and MAC and starts up", "[link][memory]") {
    auto ends = make_wire();
    CHECK(ends.a->name() == "a0");
    CHECK(ends.b->name() == "b0");
    CHECK(ends.a->mac() == kMacA);
    CHECK(ends.b->mac() == kMacB);
    CHECK(ends.a->link_up());
    CHECK(ends.b->link_up());
    CHECK(ends.a->selectable_fd() != ends.b->selectable_fd());
}

TEST_CASE("memory link: frames arrive at the other end byte-identical and in order", "[link][memory]") {
    auto ends = make_wire();
    const auto short_frame = make_frame(29, 1);
    const auto full_frame = make_frame(ecpair::wire::kMaxFrameSize, 7);
    REQUIRE(ends.a->send(short_frame));
    REQUIRE(ends.a->send(full_frame));
    REQUIRE(ends.b->send(short_frame));

    std::vector<std::uint8_t> buffer(2048);
    for (const auto* expected : {&short_frame, &full_frame}) {
        auto received = ends.b->try_receive(buffer);
        REQUIRE(received);
        REQUIRE(received->has_value());
        CHECK((*received)->size == expected->size());
        CHECK((*received)->wire_size == expected->size());
        CHECK(std::equal(expected->begin(), expected->end(), buffer.begin()));
    }
    CHECK_FALSE(ends.b->try_receive(buffer)->has_value());

    auto back = ends.a->try_receive(buffer);
    REQUIRE(back->has_value());
    CHECK(std::equal(short_frame.begin(), short_frame.end(), buffer.begin()));
    CHECK_FALSE(ends.a->try_receive(buffer)->has_value());  // not its own frames
    CHECK(ends.a->counters().delivered == 2);
    CHECK(ends.b->counters().delivered == 1);
}

TEST_CASE("memory link: a full queue drops and counts the excess", "[link][memory]") {
    auto ends = make_wire(4);
    for (std::uint8_t i = 0; i < 6; ++i) REQUIRE(ends.a->send(make_frame(60, i)));
    CHECK(ends.a->counters().delivered == 4);
    CHECK(ends.a->counters().dropped_queue_full == 2);

    std::vector<std::uint8_t> buffer(2048);
    for (std::uint8_t i = 0; i < 4; ++i) {
        REQUIRE(ends.b->try_receive(buffer)->has_value());
        CHECK(buffer[0] == i);  // the first four, oldest first
    }
    CHECK_FALSE(ends.b->try_receive(buffer)->has_value());
    REQUIRE(ends.a->send(make_frame(60, 9)));  // room again
    REQUIRE(ends.b->try_receive(buffer)->has_value());
    CHECK(buffer[0] == 9);
}

TEST_CASE("memory link: pulling the cable drops new frames and keeps queued ones", "[link][memory]") {
    auto ends = make_wire();
    REQUIRE(ends.a->send(make_frame(60, 1)));
    ends.wire->set_link_up(false);
    CHECK_FALSE(ends.a->link_up());
    CHECK_FALSE(ends.b->link_up());
    CHECK(ends.a->send(make_frame(60, 2)));  // like a NIC without carrier: accepted, lost
    CHECK(ends.b->send(make_frame(60, 3)));
    CHECK(ends.a->counters().dropped_link_down == 1);
    CHECK(ends.b->counters().dropped_link_down == 1);

    std::vector<std::uint8_t> buffer(2048);
    REQUIRE(ends.b->try_receive(buffer)->has_value());
    CHECK(buffer[0] == 1);
    CHECK_FALSE(ends.b->try_receive(buffer)->has_value());
    CHECK_FALSE(ends.a->try_receive(buffer)->has_value());

    ends.wire->set_link_up(true);
    CHECK(ends.a->link_up());
    REQUIRE(ends.a->send(make_frame(60, 4)));
    REQUIRE(ends.b->try_receive(buffer)->has_value());
    CHECK(buffer[0] == 4);
}

TEST_CASE("memory link: the selectable fd is readable exactly while frames wait", "[link][memory]") {
    auto ends = make_wire();
    const int fd = ends.b->selectable_fd();
    CHECK_FALSE(readable(fd));
    REQUIRE(ends.a->send(make_frame(60, 1)));
    REQUIRE(ends.a->send(make_frame(60, 2)));
    CHECK(readable(fd));
    CHECK_FALSE(readable(ends.a->selectable_fd()));

    std::vector<std::uint8_t> buffer(2048);
    REQUIRE(ends.b->try_receive(buffer)->has_value());
    CHECK(readable(fd));  // one frame left
    REQUIRE(ends.b->try_receive(buffer)->has_value());
    CHECK_FALSE(readable(fd));
}

TEST_CASE("memory link: receive gives nothing when the timeout passes without a frame", "[link][memory]") {
    auto ends = make_wire();
    std::vector<std::uint8_t> buffer(2048);
    auto received = ends.b->receive(buffer, 5ms);
    REQUIRE(received);
    CHECK_FALSE(received->has_value());
    auto immediate = ends.b->receive(buffer, 0ns);
    REQUIRE(immediate);
    CHECK_FALSE(immediate->has_value());
}

TEST_CASE("memory link: a blocked receive wakes up for a frame sent by another thread", "[link][memory]") {
    auto ends = make_wire();
    std::vector<std::uint8_t> buffer(2048);
    const auto frame = make_frame(100, 42);
    const auto before = ecpair::link::Clock::now();
    bool sent = false;
    std::thread sender([&] { sent = ends.a->send(frame).has_value(); });
    auto received = ends.b->receive(buffer, 60s);  // returns as soon as the frame is there
    sender.join();
    CHECK(sent);
    REQUIRE(received);
    REQUIRE(received->has_value());
    CHECK((*received)->size == frame.size());
    CHECK(std::equal(frame.begin(), frame.end(), buffer.begin()));
    CHECK((*received)->timestamp >= before);
    CHECK((*received)->capture_time.time_since_epoch().count() > 0);
}

TEST_CASE("memory link: frames larger than 1518 bytes are refused", "[link][memory]") {
    auto ends = make_wire();
    auto too_large = ends.a->send(make_frame(ecpair::wire::kMaxFrameSizeVlan + 1, 0));
    REQUIRE_FALSE(too_large);
    CHECK(too_large.error().code == LinkErrc::FrameTooLarge);
    CHECK(too_large.error().message.find("a0") != std::string::npos);
    CHECK(ends.a->send(make_frame(ecpair::wire::kMaxFrameSizeVlan, 0)));
    CHECK(ends.a->counters().delivered == 1);
}

TEST_CASE("memory link: a small buffer gets the frame's start and its full size", "[link][memory]") {
    auto ends = make_wire();
    const auto frame = make_frame(200, 3);
    REQUIRE(ends.a->send(frame));
    std::vector<std::uint8_t> buffer(64);
    auto received = ends.b->try_receive(buffer);
    REQUIRE(received->has_value());
    CHECK((*received)->size == 64);
    CHECK((*received)->wire_size == 200);
    CHECK(std::equal(buffer.begin(), buffer.end(), frame.begin()));
}

TEST_CASE("memory link: a zero-sized queue is refused", "[link][memory]") {
    CHECK_THROWS_AS(make_wire(0), std::invalid_argument);
}

TEST_CASE("memory wire watcher: reports each change under both names, once", "[link][memory]") {
    auto ends = make_wire();
    auto watcher = ends.wire->watch();
    CHECK(watcher->is_up("a0") == true);
    CHECK(watcher->is_up("b0") == true);
    CHECK_FALSE(watcher->is_up("other").has_value());
    CHECK_FALSE(readable(watcher->selectable_fd()));
    CHECK(watcher->read_changes().empty());

    ends.wire->set_link_up(false);
    ends.wire->set_link_up(false);  // no change, no report
    CHECK(readable(watcher->selectable_fd()));
    auto changes = watcher->read_changes();
    REQUIRE(changes.size() == 2);
    CHECK(changes[0].interface == "a0");
    CHECK(changes[1].interface == "b0");
    CHECK_FALSE(changes[0].up);
    CHECK_FALSE(changes[1].up);
    CHECK_FALSE(readable(watcher->selectable_fd()));
    CHECK(watcher->is_up("a0") == false);

    ends.wire->set_link_up(true);
    changes = watcher->read_changes();
    REQUIRE(changes.size() == 2);
    CHECK(changes[0].up);
    CHECK(changes[1].up);
}

TEST_CASE("memory wire watcher: outlives the ends and stops with its own destruction", "[link][memory]") {
    auto ends = make_wire();
    auto first = ends.wire->watch();
    {
        auto second = ends.wire->watch();
        ends.wire->set_link_up(false);
        CHECK(second->read_changes().size() == 2);
    }
    ends.a.reset();
    ends.b.reset();
    ends.wire->set_link_up(true);  // the destroyed watcher is not called
    CHECK(first->read_changes().size() == 4);
}
