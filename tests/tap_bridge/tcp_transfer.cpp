#include "tcp_transfer.hpp"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <sys/socket.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <cstring>
#include <stdexcept>
#include <vector>

#include "ecpair/common/crc32.hpp"

namespace ecpair::test {
namespace {

sockaddr_in address_of(const std::string& address, std::uint16_t port) {
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_port = htons(port);
    if (inet_pton(AF_INET, address.c_str(), &a.sin_addr) != 1) throw std::runtime_error("bad address " + address);
    return a;
}

void set_timeout(int fd, std::chrono::seconds timeout) {
    timeval tv{};
    tv.tv_sec = static_cast<time_t>(timeout.count());
    ::setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
    ::setsockopt(fd, SOL_SOCKET, SO_SNDTIMEO, &tv, sizeof tv);
}

}  // namespace

TcpReceiver::TcpReceiver(const TestNamespace& ns, const std::string& address, std::uint16_t port,
                         std::chrono::seconds timeout)
    : timeout_(timeout) {
    {
        NamespaceScope inside(ns);
        listen_fd_ = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
    }
    if (listen_fd_ < 0) throw std::runtime_error("socket: " + std::string(std::strerror(errno)));
    const int one = 1;
    ::setsockopt(listen_fd_, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one);
    const auto a = address_of(address, port);
    if (::bind(listen_fd_, reinterpret_cast<const sockaddr*>(&a), sizeof a) != 0 || ::listen(listen_fd_, 1) != 0) {
        const std::string why = std::strerror(errno);
        ::close(listen_fd_);
        throw std::runtime_error("cannot listen on " + address + ": " + why);
    }
    set_timeout(listen_fd_, timeout_);
    thread_ = std::thread([this] {
        const int fd = ::accept(listen_fd_, nullptr, nullptr);
        if (fd < 0) {
            summary_.error = "accept: " + std::string(std::strerror(errno));
            done_ = true;
            return;
        }
        set_timeout(fd, timeout_);
        std::vector<std::uint8_t> buffer(65536);
        for (;;) {
            const auto n = ::recv(fd, buffer.data(), buffer.size(), 0);
            if (n == 0) break;
            if (n < 0) {
                summary_.error = "recv: " + std::string(std::strerror(errno));
                break;
            }
            summary_.crc = crc32(ConstBytes(buffer.data(), static_cast<std::size_t>(n)), summary_.crc);
            summary_.bytes += static_cast<std::size_t>(n);
        }
        ::close(fd);
        done_ = true;
    });
}

TcpReceiver::~TcpReceiver() {
    ::shutdown(listen_fd_, SHUT_RDWR);
    if (thread_.joinable()) thread_.join();
    ::close(listen_fd_);
}

StreamSummary TcpReceiver::wait() {
    if (thread_.joinable()) thread_.join();
    return summary_;
}

TcpSender::TcpSender(const TestNamespace& ns, const std::string& address, std::uint16_t port,
                     std::chrono::seconds timeout) {
    const auto a = address_of(address, port);
    const auto give_up = std::chrono::steady_clock::now() + timeout;
    while (std::chrono::steady_clock::now() < give_up) {
        {
            NamespaceScope inside(ns);
            fd_ = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
        }
        if (fd_ < 0) break;
        set_timeout(fd_, timeout);
        if (::connect(fd_, reinterpret_cast<const sockaddr*>(&a), sizeof a) == 0) return;
        summary_.error = "connect: " + std::string(std::strerror(errno));
        ::close(fd_);
        fd_ = -1;
        std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
}

TcpSender::~TcpSender() { close(); }

bool TcpSender::send(std::size_t bytes) {
    if (fd_ < 0) return false;
    std::array<std::uint8_t, 16384> chunk{};
    while (bytes > 0) {
        const std::size_t n = std::min(bytes, chunk.size());
        for (std::size_t i = 0; i < n; ++i) {
            // xorshift64: a stream no compression or coincidence makes look right
            state_ ^= state_ << 13;
            state_ ^= state_ >> 7;
            state_ ^= state_ << 17;
            chunk[i] = static_cast<std::uint8_t>(state_);
        }
        std::size_t at = 0;
        while (at < n) {
            const auto sent = ::send(fd_, chunk.data() + at, n - at, MSG_NOSIGNAL);
            if (sent < 0) {
                summary_.error = "send: " + std::string(std::strerror(errno));
                return false;
            }
            at += static_cast<std::size_t>(sent);
        }
        summary_.crc = crc32(ConstBytes(chunk.data(), n), summary_.crc);
        summary_.bytes += n;
        bytes -= n;
    }
    return true;
}

void TcpSender::close() {
    if (fd_ < 0) return;
    ::close(fd_);
    fd_ = -1;
}

}  // namespace ecpair::test
