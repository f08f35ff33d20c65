#pragma once
// A TCP transfer between two network namespaces for the bridge tests: the
// receiver listens inside one namespace and checksums what arrives, the
// sender connects from another and checksums what it sends (CRC-32 of a
// deterministic pseudo-random stream). Every socket has a timeout, so a
// broken bridge fails the test instead of hanging it.

#include <atomic>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <string>
#include <thread>

#include "netns.hpp"

namespace ecpair::test {

struct StreamSummary {
    std::size_t bytes = 0;
    std::uint32_t crc = 0;
    std::string error;  // empty when the stream ended cleanly
};

class TcpReceiver {
public:
    TcpReceiver(const TestNamespace& ns, const std::string& address, std::uint16_t port,
                std::chrono::seconds timeout = std::chrono::seconds(30));
    ~TcpReceiver();
    TcpReceiver(const TcpReceiver&) = delete;
    TcpReceiver& operator=(const TcpReceiver&) = delete;

    // Waits for the sender to close (bounded by the timeout given).
    StreamSummary wait();

private:
    int listen_fd_ = -1;
    std::chrono::seconds timeout_;
    std::thread thread_;
    StreamSummary summary_;
    std::atomic<bool> done_{false};
};

class TcpSender {
public:
    // Connects from inside `ns` (retrying until the timeout: the bridge may still be starting).
    TcpSender(const TestNamespace& ns, const std::string& address, std::uint16_t port,
              std::chrono::seconds timeout = std::chrono::seconds(30));
    ~TcpSender();
    TcpSender(const TcpSender&) = delete;
    TcpSender& operator=(const TcpSender&) = delete;

    bool connected() const { return fd_ >= 0; }
    // Sends the next `bytes` of the stream; false (and error set) on failure.
    bool send(std::size_t bytes);
    void close();
    const StreamSummary& summary() const { return summary_; }

private:
    int fd_ = -1;
    std::uint64_t state_ = 0x9E3779B97F4A7C15ull;  // the stream's generator
    StreamSummary summary_;
};

}  // namespace ecpair::test
