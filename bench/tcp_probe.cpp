// ecpair-tcp-probe: the TCP end points of the TAP bridge benchmark, run
// inside the controllers' namespaces with `ip netns exec`.
//
//   ecpair-tcp-probe listen ADDRESS PORT        prints "received BYTES in SECONDS s"
//   ecpair-tcp-probe send ADDRESS PORT SECONDS  sends for SECONDS, then closes
//
// The receiver times from the first byte to the end of the stream, so the
// figure is the bridge's steady rate, not the connection setup.

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <thread>
#include <vector>

namespace {

sockaddr_in address_of(const char* address, const char* port) {
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_port = htons(static_cast<std::uint16_t>(std::atoi(port)));
    if (inet_pton(AF_INET, address, &a.sin_addr) != 1) {
        std::fprintf(stderr, "ecpair-tcp-probe: bad address %s\n", address);
        std::exit(2);
    }
    return a;
}

int listen_and_count(const sockaddr_in& a) {
    const int server = ::socket(AF_INET, SOCK_STREAM, 0);
    const int one = 1;
    ::setsockopt(server, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one);
    if (::bind(server, reinterpret_cast<const sockaddr*>(&a), sizeof a) != 0 || ::listen(server, 1) != 0) {
        std::perror("ecpair-tcp-probe: listen");
        return 1;
    }
    const int fd = ::accept(server, nullptr, nullptr);
    if (fd < 0) {
        std::perror("ecpair-tcp-probe: accept");
        return 1;
    }
    std::vector<char> buffer(1 << 16);
    std::size_t bytes = 0;
    std::chrono::steady_clock::time_point first{};
    for (;;) {
        const auto n = ::recv(fd, buffer.data(), buffer.size(), 0);
        if (n <= 0) break;
        if (bytes == 0) first = std::chrono::steady_clock::now();
        bytes += static_cast<std::size_t>(n);
    }
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - first).count();
    std::printf("received %zu in %.3f s\n", bytes, seconds);
    return 0;
}

int send_for(const sockaddr_in& a, double seconds) {
    int fd = -1;
    for (int attempt = 0; attempt < 100; ++attempt) {
        fd = ::socket(AF_INET, SOCK_STREAM, 0);
        if (::connect(fd, reinterpret_cast<const sockaddr*>(&a), sizeof a) == 0) break;
        ::close(fd);
        fd = -1;
        std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
    if (fd < 0) {
        std::perror("ecpair-tcp-probe: connect");
        return 1;
    }
    std::vector<char> buffer(1 << 16, 'x');
    const auto stop = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
    while (std::chrono::steady_clock::now() < stop) {
        if (::send(fd, buffer.data(), buffer.size(), MSG_NOSIGNAL) < 0) {
            std::perror("ecpair-tcp-probe: send");
            return 1;
        }
    }
    ::close(fd);
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    if (argc == 4 && std::strcmp(argv[1], "listen") == 0) return listen_and_count(address_of(argv[2], argv[3]));
    if (argc == 5 && std::strcmp(argv[1], "send") == 0) return send_for(address_of(argv[2], argv[3]), std::atof(argv[4]));
    std::fprintf(stderr, "usage: ecpair-tcp-probe listen ADDRESS PORT | send ADDRESS PORT SECONDS\n");
    return 2;
}
