// The acyclic queue between a worker thread (blocking exchange) and a
// stand-in cycle loop that plays the slaves: completion, re-send of lost
// frames, deadline, refusal.

#include <atomic>
#include <thread>

#include <catch2/catch.hpp>

#include "ecpair/master/acyclic_queue.hpp"

using namespace ecpair;
using namespace ecpair::master;
using namespace std::chrono_literals;

namespace {

// Runs "cycles" until stopped: frames are answered (every datagram gets its
// first data byte + 1 and WKC 1) unless `lose` says to drop them.
class FakeCycle {
public:
    FakeCycle(AcyclicQueue& q, std::function<bool(int)> lose) : queue_(q), lose_(std::move(lose)) {
        thread_ = std::thread([this] { run(); });
    }
    ~FakeCycle() {
        stop_ = true;
        thread_.join();
    }
    int frames() const { return frames_; }

private:
    void run() {
        std::array<std::uint8_t, wire::kMaxFrameSize> buffer{};
        while (!stop_) {
            wire::FrameBuilder builder(buffer, wire::EthernetHeader{});
            const auto now = link::Clock::now();
            const auto batch = queue_.fill_frame(builder, now);
            if (batch) {
                auto frame = builder.finish();
                const int n = frames_++;
                auto view = wire::FrameView::parse(frame);
                if (lose_(n) || !view) {
                    queue_.complete(*batch, nullptr, now);
                } else {
                    for (auto d : *view) {
                        if (!d.data().empty()) d.data()[0] = static_cast<std::uint8_t>(d.data()[0] + 1);
                        d.set_wkc(1);
                    }
                    auto returned = wire::ConstFrameView::parse(std::span<const std::uint8_t>(frame));
                    queue_.complete(*batch, &*returned, now);
                }
            }
            std::this_thread::sleep_for(1ms);
        }
    }

    AcyclicQueue& queue_;
    std::function<bool(int)> lose_;
    std::atomic<bool> stop_{false};
    std::atomic<int> frames_{0};
    std::thread thread_;
};

bus::DatagramRequest request(std::uint8_t first_byte, std::chrono::milliseconds timeout = 50ms,
                             std::uint32_t retries = 2) {
    bus::DatagramRequest r;
    r.command = wire::Command::Fprd;
    r.address = wire::DatagramHeader::physical(0x1001, 0x130);
    r.data = {first_byte, 0};
    r.timeout = timeout;
    r.retries = retries;
    return r;
}

}  // namespace

TEST_CASE("a request is answered through the cycle", "[acyclic]") {
    AcyclicQueue queue(2);
    FakeCycle cycle(queue, [](int) { return false; });
    auto reply = queue.exchange(request(41));
    REQUIRE(reply);
    CHECK(reply->data == std::vector<std::uint8_t>{42, 0});
    CHECK(reply->wkc == 1);
}

TEST_CASE("a lost frame is sent again and then answered", "[acyclic]") {
    AcyclicQueue queue(1);
    FakeCycle cycle(queue, [](int n) { return n < 2; });  // the first two frames are lost
    auto reply = queue.exchange(request(1, 500ms, 3));
    REQUIRE(reply);
    CHECK(reply->data[0] == 2);
    CHECK(queue.resent() >= 2);
}

TEST_CASE("a request whose frames are always lost times out", "[acyclic]") {
    AcyclicQueue queue(1);
    FakeCycle cycle(queue, [](int) { return true; });
    auto reply = queue.exchange(request(1, 10ms, 1));
    REQUIRE_FALSE(reply);
    CHECK(reply.error().code == bus::BusErrc::Timeout);
}

TEST_CASE("an INACTIVE master refuses requests", "[acyclic]") {
    AcyclicQueue queue(1);
    queue.refuse(bus::BusErrc::MasterRedStateInactive);
    auto reply = queue.exchange(request(1));
    REQUIRE_FALSE(reply);
    CHECK(reply.error().code == bus::BusErrc::MasterRedStateInactive);
    queue.refuse(std::nullopt);
    FakeCycle cycle(queue, [](int) { return false; });
    CHECK(queue.exchange(request(1)));
}

TEST_CASE("pending requests are cancelled when the master turns INACTIVE", "[acyclic]") {
    AcyclicQueue queue(1);  // no cycle runs: the request stays queued
    std::optional<bus::BusErrc> code;
    std::thread worker([&] {
        auto reply = queue.exchange(request(1, 5000ms, 0));
        if (!reply) code = reply.error().code;
    });
    std::this_thread::sleep_for(50ms);
    queue.refuse(bus::BusErrc::MasterRedStateInactive);
    worker.join();
    REQUIRE(code);
    CHECK(*code == bus::BusErrc::MasterRedStateInactive);
}

TEST_CASE("many requests from several workers all complete with their own data", "[acyclic]") {
    AcyclicQueue queue(2);
    FakeCycle cycle(queue, [](int n) { return n % 5 == 3; });
    std::atomic<int> good{0};
    std::vector<std::thread> workers;
    for (int w = 0; w < 4; ++w) {
        workers.emplace_back([&, w] {
            for (int i = 0; i < 20; ++i) {
                const auto v = static_cast<std::uint8_t>(w * 50 + i);
                auto reply = queue.exchange(request(v, 200ms, 5));
                if (reply && reply->data[0] == v + 1) ++good;
            }
        });
    }
    for (auto& t : workers) t.join();
    CHECK(good == 80);
}

TEST_CASE("a caller's requests go out together and each gets its own reply", "[acyclic]") {
    AcyclicQueue queue(2);
    FakeCycle cycle(queue, [](int) { return false; });
    std::vector<bus::DatagramRequest> requests;
    for (std::uint8_t v = 0; v < 40; ++v) requests.push_back(request(v));
    const auto replies = queue.exchange_all(requests);
    REQUIRE(replies.size() == 40);
    for (std::size_t i = 0; i < replies.size(); ++i) {
        INFO("request " << i);
        REQUIRE(replies[i]);
        CHECK(replies[i]->data[0] == i + 1);
    }
    // Queued at once: a full frame of 32 datagrams and one with the other 8.
    CHECK(cycle.frames() == 2);
}

TEST_CASE("one caller's requests fail and succeed one by one", "[acyclic]") {
    AcyclicQueue queue(1);
    FakeCycle cycle(queue, [](int n) { return n == 0; });  // the first frame is lost, then sent again
    std::vector<bus::DatagramRequest> requests{request(7, 200ms, 3), request(8, 200ms, 3), request(9, 200ms, 3)};
    requests[1].data.assign(wire::kMaxDatagramData + 1, 0);
    const auto replies = queue.exchange_all(requests);
    REQUIRE(replies.size() == 3);
    REQUIRE(replies[0]);
    CHECK(replies[0]->data[0] == 8);
    REQUIRE_FALSE(replies[1]);
    CHECK(replies[1].error().code == bus::BusErrc::InvalidRequest);
    REQUIRE(replies[2]);
    CHECK(replies[2]->data[0] == 10);
    CHECK(queue.resent() == 2);
}

TEST_CASE("a caller's requests are refused together", "[acyclic]") {
    AcyclicQueue queue(1);
    queue.refuse(bus::BusErrc::MasterRedStateInactive);
    const std::vector<bus::DatagramRequest> requests{request(1), request(2)};
    for (const auto& reply : queue.exchange_all(requests)) {
        REQUIRE_FALSE(reply);
        CHECK(reply.error().code == bus::BusErrc::MasterRedStateInactive);
    }
}

TEST_CASE("requests a stopped cycle never took time out", "[acyclic]") {
    AcyclicQueue queue(1);  // no cycle runs
    const std::vector<bus::DatagramRequest> requests{request(1, 10ms, 0), request(2, 10ms, 0)};
    const auto replies = queue.exchange_all(requests);
    REQUIRE(replies.size() == 2);
    for (const auto& reply : replies) {
        REQUIRE_FALSE(reply);
        CHECK(reply.error().code == bus::BusErrc::Timeout);
        CHECK(reply.error().message == "the cycle did not send the request");
    }
}
