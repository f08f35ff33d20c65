#pragma once
// ecpaird's operator socket (design.md §6): a Unix stream socket with the
// configured owner group and permission bits, serving length-delimited
// protobuf Requests (proto/ecpair/control.proto) on the control thread's
// Boost.Asio io_context. The daemon answers through ControlHandler; events
// are pushed to every client that asked to watch them.
//
// Hardening: the socket file never has more permissions than configured,
// not even between bind and chmod (connecting needs write permission on it:
// that is what refuses other users); a client must send a whole request
// within request_timeout of connecting or of its last answer (watchers
// excepted), else it is disconnected; at most max_clients are served, more
// are answered "busy" and closed; a watcher that does not read its events is
// dropped before its queue grows without bound; running out of descriptors
// pauses accepting instead of ending it. Status replies carry these counters.

#include <chrono>
#include <cstdint>
#include <deque>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <utility>  // Boost 1.74 asio uses std::exchange without including it

#include <boost/asio.hpp>

#include "ecpair/common/expected.hpp"
#include "ecpair/control.pb.h"

namespace ecpair::control {

class ControlHandler {
public:
    virtual ~ControlHandler() = default;
    virtual StatusReply status(const StatusRequest& request) = 0;
    // nullopt when accepted, else why not.
    virtual std::optional<std::string> set_master_state(const SetMasterStateRequest& request) = 0;
    virtual std::optional<std::string> set_red_state(const SetRedStateRequest& request) = 0;
    virtual ImageHistoryReply image_history(const ImageHistoryRequest& request) = 0;
    virtual std::optional<std::string> switchover(const SwitchoverRequest& request) = 0;
    virtual std::optional<std::string> force_standby(const ForceStandbyRequest& request) = 0;
};

struct SocketSettings {
    std::string path;
    unsigned mode = 0660;
    std::string group;  // empty: keep the daemon's group
    std::chrono::milliseconds request_timeout{5000};
    std::size_t max_clients = 2048;
};

struct SocketCounters {
    std::uint64_t refused_busy = 0;
    std::uint64_t timed_out = 0;
    std::uint64_t malformed = 0;
    std::uint64_t slow_watchers = 0;
};

class ControlServer {
public:
    ControlServer(boost::asio::io_context& io, ControlHandler& handler, SocketSettings settings);
    ~ControlServer();

    // Binds and listens (a stale socket file is replaced, a live one refused).
    Expected<void, std::string> open();
    // Sends an event to every watching client and keeps it in the backlog
    // that a client starting to watch gets first (so nothing that happened
    // since the daemon started is missed). Call on the io_context's thread.
    void publish(const EventMessage& event);
    static constexpr std::size_t kBacklog = 256;
    // Messages queued for one client beyond which it is dropped (a watcher that does not read).
    static constexpr std::size_t kMaxQueued = 4096;
    std::size_t clients() const;
    const SocketCounters& counters() const { return counters_; }

private:
    class Session;
    void accept();
    void accept_later();
    void fill_status(OperatorSocketStatus& out) const;

    boost::asio::io_context& io_;
    ControlHandler& handler_;
    SocketSettings settings_;
    boost::asio::local::stream_protocol::acceptor acceptor_;
    boost::asio::steady_timer accept_pause_;
    std::vector<std::weak_ptr<Session>> sessions_;
    std::deque<EventMessage> backlog_;
    SocketCounters counters_;
};

}  // namespace ecpair::control
