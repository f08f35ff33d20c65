#pragma once
// ecpaird's operator socket (design.md §6): a Unix stream socket with the
// configured owner group and permission bits, serving length-delimited
// protobuf Requests (proto/ecpair/control.proto) on the control thread's
// Boost.Asio io_context. The daemon answers through ControlHandler; events
// are pushed to every client that asked to watch them.

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
    std::size_t clients() const;

private:
    class Session;
    void accept();

    boost::asio::io_context& io_;
    ControlHandler& handler_;
    SocketSettings settings_;
    boost::asio::local::stream_protocol::acceptor acceptor_;
    std::vector<std::weak_ptr<Session>> sessions_;
    std::deque<EventMessage> backlog_;
};

}  // namespace ecpair::control
