#pragma once
// One client of the operator socket: it reads requests with the incremental
// delimited reader, answers each, and keeps a queue of outgoing messages so
// that an event published while a write is in flight is not interleaved
// with it. A client that sends garbage gets one error Response and is
// closed; one that takes longer than request_timeout for a request (from
// connecting, or from its last answer) is closed; a watcher whose queue
// passes ControlServer::kMaxQueued is dropped.

#include <array>
#include <deque>
#include <memory>
#include <optional>
#include <string>

#include "ecpair/control/control_server.hpp"
#include "ecpair/control/delimited.hpp"

namespace ecpair::control {

class ControlServer::Session : public std::enable_shared_from_this<Session> {
public:
    Session(boost::asio::local::stream_protocol::socket socket, ControlServer& server);

    void start();
    bool watching() const { return watching_; }
    void send(const Response& response);
    // Answers "busy" and closes: the server serves max_clients already.
    void refuse(const std::string& why);

private:
    void read();
    void handle(const Request& request);
    static void answer(Response& response, const std::optional<std::string>& error);
    void reject(const std::string& why);
    void write();
    void arm_request_timer();
    void close();

    boost::asio::local::stream_protocol::socket socket_;
    ControlServer& server_;
    boost::asio::steady_timer request_timer_;
    std::array<char, 4096> buffer_{};
    DelimitedReader reader_;
    std::deque<std::string> outbox_;
    bool watching_ = false;
    bool closing_ = false;
    bool closed_ = false;
};

}  // namespace ecpair::control
