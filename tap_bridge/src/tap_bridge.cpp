// The TAP I/O thread: poll() on three fds, then
//   wake fd   -> write every frame the channel delivered to the TAP
//   TAP fd    -> read what the kernel sends (a bounded batch) into the channel
//   stop fd   -> leave
// Frames are copied out of the queue before the write() so that no lock is
// held across a system call.

#include "ecpair/tap_bridge/tap_bridge.hpp"

#include <poll.h>
#include <sys/eventfd.h>
#include <unistd.h>

#include <array>
#include <random>

#include <fmt/format.h>

#include "ecpair/common/log.hpp"
#include "tap_device.hpp"
#include "tap_bridge_log.hpp"

namespace ecpair::tap_bridge {
namespace {

// Frames read per wake-up before the thread looks at its other fds again.
constexpr int kReadBatch = 64;

void signal(int fd) {
    const std::uint64_t one = 1;
    [[maybe_unused]] const auto n = ::write(fd, &one, sizeof one);
}

void drain(int fd) {
    std::uint64_t value = 0;
    [[maybe_unused]] const auto n = ::read(fd, &value, sizeof value);
}

std::uint32_t random_session() {
    std::random_device device;
    std::uint32_t session = 0;
    while (session == 0) session = device();
    return session;
}

}  // namespace

wire::MacAddress default_mac(std::string_view instance, std::string_view tap) {
    std::uint64_t hash = 0xcbf29ce484222325ull;  // FNV-1a 64
    const auto mix = [&hash](std::string_view text) {
        for (const char c : text) hash = (hash ^ static_cast<std::uint8_t>(c)) * 0x100000001b3ull;
    };
    mix(instance);
    mix("/");
    mix(tap);
    return wire::MacAddress{{0x02, 0xec, static_cast<std::uint8_t>(hash >> 24), static_cast<std::uint8_t>(hash >> 16),
                             static_cast<std::uint8_t>(hash >> 8), static_cast<std::uint8_t>(hash)}};
}

Expected<std::size_t, std::string> TapBridge::mtu_for(const TapBridgeOptions& options) {
    if (options.poll_size < kMinPollData || options.poll_size > kMaxBridgeDatagramData) {
        return unexpected(fmt::format("tap poll size {} is outside {}..{} bytes", options.poll_size, kMinPollData,
                                      kMaxBridgeDatagramData));
    }
    const std::size_t fits = largest_mtu(options.poll_size);
    if (!options.mtu) return fits;
    // 68 is the smallest MTU IPv4 allows (RFC 791).
    if (*options.mtu > fits || *options.mtu < 68) {
        return unexpected(fmt::format("tap MTU {} does not fit one bridge datagram of one EtherCAT frame{}: the largest "
                                      "that fits is {} (the smallest allowed is 68)",
                                      *options.mtu,
                                      options.poll_size < kMaxBridgeDatagramData
                                          ? fmt::format(" with a poll of {} bytes", options.poll_size)
                                          : std::string(),
                                      fits));
    }
    return *options.mtu;
}

Expected<std::unique_ptr<TapBridge>, std::string> TapBridge::open(const TapBridgeOptions& options) {
    auto mtu = mtu_for(options);
    if (!mtu) return unexpected(mtu.error());
    std::size_t ipv4 = 0;
    for (const auto& a : options.addresses) ipv4 += a.family == InterfaceAddress::Family::Ipv4 ? 1 : 0;
    if (ipv4 > 1) return unexpected(std::string("tap: at most one IPv4 address (any number of IPv6)"));
    auto device = TapDevice::open(TapDeviceOptions{options.name, options.mac, *mtu, options.addresses});
    if (!device) return unexpected(device.error());
    const int wake = ::eventfd(0, EFD_CLOEXEC | EFD_NONBLOCK);
    const int stop = ::eventfd(0, EFD_CLOEXEC | EFD_NONBLOCK);
    if (wake < 0 || stop < 0) {
        if (wake >= 0) ::close(wake);
        if (stop >= 0) ::close(stop);
        return unexpected(std::string("tap: cannot create eventfds"));
    }
    return std::unique_ptr<TapBridge>(new TapBridge(options, *mtu, std::move(*device), wake, stop, random_session()));
}

TapBridge::TapBridge(const TapBridgeOptions& options, std::size_t mtu, std::unique_ptr<TapDevice> device, int wake_fd,
                     int stop_fd, std::uint32_t session)
    : options_(options),
      mtu_(mtu),
      device_(std::move(device)),
      wake_fd_(wake_fd),
      stop_fd_(stop_fd),
      channel_(BridgeChannelOptions{session, options.poll_size, options.queue_frames}) {
    channel_.set_on_delivery([this] { signal(wake_fd_); });
    std::string addresses;
    // Appended piecewise, not `" " + a.to_string()`: GCC 12 at -O3 reports a
    // false -Wrestrict in the inlined operator+(const char*, std::string&&).
    for (const auto& a : options_.addresses) {
        addresses += ' ';
        addresses += a.to_string();
    }
    log()->info("TAP {} (MAC {}, MTU {}{}{}), session {:08x}, polls of {} bytes, queues of {} frames", device_->name(),
                device_->mac().to_string(), mtu_, addresses.empty() ? "" : ",", addresses, session, options_.poll_size,
                options_.queue_frames);
}

TapBridge::~TapBridge() {
    stop();
    ::close(wake_fd_);
    ::close(stop_fd_);
}

void TapBridge::start() {
    if (thread_.joinable()) return;
    thread_ = std::thread([this] { run(); });
}

void TapBridge::stop() {
    if (!thread_.joinable()) return;
    signal(stop_fd_);
    thread_.join();
}

void TapBridge::run() {
    std::array<pollfd, 3> fds{{{device_->fd(), POLLIN, 0}, {wake_fd_, POLLIN, 0}, {stop_fd_, POLLIN, 0}}};
    for (;;) {
        if (::poll(fds.data(), fds.size(), -1) < 0) {
            if (errno == EINTR) continue;
            log()->error("TAP {}: poll failed: {}; the bridge stops", device_->name(), std::strerror(errno));
            return;
        }
        if (fds[2].revents != 0) return;
        if (fds[1].revents != 0) {
            drain(wake_fd_);
            write_tap();
        }
        if (fds[0].revents & (POLLERR | POLLHUP | POLLNVAL)) {
            log()->error("TAP {}: the device went away; the bridge stops", device_->name());
            return;
        }
        if (fds[0].revents & POLLIN) read_tap();
    }
}

void TapBridge::read_tap() {
    std::array<std::uint8_t, FrameQueue::kMaxFrame + 1> buffer{};
    for (int i = 0; i < kReadBatch; ++i) {
        const long n = device_->read(buffer);
        if (n <= 0) return;
        // One byte more than any frame: a read that fills it was a frame too large for us.
        channel_.offer(ConstBytes(buffer.data(), static_cast<std::size_t>(n)));
    }
}

void TapBridge::write_tap() {
    std::array<std::uint8_t, FrameQueue::kMaxFrame> buffer{};
    for (;;) {
        std::size_t size = 0;
        const auto taken = channel_.inbound().pop_while(
            [&](ConstBytes frame) {
                std::copy(frame.begin(), frame.end(), buffer.begin());
                size = frame.size();
                return true;
            },
            1);
        if (taken == 0) return;
        if (!device_->write(ConstBytes(buffer.data(), size))) channel_.count_tap_write_failure();
    }
}

TapBridgeStatus TapBridge::status() const {
    TapBridgeStatus s;
    s.name = device_->name();
    for (const auto& a : options_.addresses) s.addresses.push_back(a.to_string());
    s.mac = device_->mac().to_string();
    s.mtu = mtu_;
    s.flow = channel_.flow();
    s.counters = channel_.counters();
    s.outbound_depth = channel_.outbound_depth();
    s.inbound_depth = channel_.inbound_depth();
    s.queue_capacity = channel_.queue_capacity();
    return s;
}

}  // namespace ecpair::tap_bridge
