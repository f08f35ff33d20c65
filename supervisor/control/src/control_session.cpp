#include "control_session.hpp"

#include "ecpair/common/log.hpp"

namespace ecpair::control {

namespace asio = boost::asio;
using stream_protocol = asio::local::stream_protocol;

ControlServer::Session::Session(stream_protocol::socket socket, ControlServer& server)
    : socket_(std::move(socket)), server_(server), request_timer_(server.io_) {}

void ControlServer::Session::start() {
    arm_request_timer();
    read();
}

void ControlServer::Session::arm_request_timer() {
    request_timer_.expires_after(server_.settings_.request_timeout);
    request_timer_.async_wait([self = weak_from_this()](const boost::system::error_code& ec) {
        auto session = self.lock();
        if (ec || !session || session->watching_ || session->closed_) return;
        ++session->server_.counters_.timed_out;
        logger("control")->debug("operator client closed: no whole request within {} ms",
                                 session->server_.settings_.request_timeout.count());
        session->close();
    });
}

void ControlServer::Session::close() {
    if (closed_) return;
    closed_ = true;
    request_timer_.cancel();
    boost::system::error_code ignored;
    socket_.shutdown(stream_protocol::socket::shutdown_both, ignored);
    socket_.close(ignored);
}

void ControlServer::Session::read() {
    auto self = shared_from_this();
    socket_.async_read_some(asio::buffer(buffer_), [this, self](const boost::system::error_code& ec, std::size_t n) {
        if (ec || closed_) {  // the client left (or was closed): the session ends with its last reference
            close();
            return;
        }
        reader_.feed(std::string_view(buffer_.data(), n));
        std::string payload;
        for (;;) {
            const auto result = reader_.next(payload);
            if (result == DelimitedReader::Result::NeedMore) break;
            if (result == DelimitedReader::Result::Error) {
                reject(reader_.error());
                return;
            }
            Request request;
            if (!request.ParseFromString(payload)) {
                reject("the request is not an ecpair.control.Request");
                return;
            }
            handle(request);
            if (closed_) return;
        }
        read();
    });
}

void ControlServer::Session::handle(const Request& request) {
    Response response;
    ControlHandler& handler = server_.handler_;
    switch (request.kind_case()) {
        case Request::kStatus:
            *response.mutable_status() = handler.status(request.status());
            server_.fill_status(*response.mutable_status()->mutable_operator_socket());
            response.set_ok(true);
            break;
        case Request::kWatchEvents:
            watching_ = true;
            request_timer_.cancel();
            response.set_ok(true);
            send(response);
            for (const auto& event : server_.backlog_) {
                Response past;
                past.set_ok(true);
                *past.mutable_event() = event;
                send(past);
            }
            return;
        case Request::kSetMasterState: answer(response, handler.set_master_state(request.set_master_state())); break;
        case Request::kSetRedState: answer(response, handler.set_red_state(request.set_red_state())); break;
        case Request::kImageHistory:
            *response.mutable_image_history() = handler.image_history(request.image_history());
            response.set_ok(true);
            break;
        case Request::kSwitchover: answer(response, handler.switchover(request.switchover())); break;
        case Request::kForceStandby: answer(response, handler.force_standby(request.force_standby())); break;
        case Request::KIND_NOT_SET:
            response.set_error(
                "empty request: set one of status, watch_events, set_master_state, set_red_state, image_history, "
                "switchover, force_standby");
            break;
    }
    send(response);
    arm_request_timer();  // the next request has the same time
}

void ControlServer::Session::answer(Response& response, const std::optional<std::string>& error) {
    if (error) {
        response.set_error(*error);
    } else {
        response.set_ok(true);
    }
}

void ControlServer::Session::reject(const std::string& why) {
    ++server_.counters_.malformed;
    Response response;
    response.set_error(why);
    closing_ = true;
    send(response);
}

void ControlServer::Session::refuse(const std::string& why) {
    Response response;
    response.set_error(why);
    closing_ = true;
    send(response);
}

void ControlServer::Session::send(const Response& response) {
    if (closed_) return;
    if (outbox_.size() >= kMaxQueued) {
        ++server_.counters_.slow_watchers;
        logger("control")->warn("operator client dropped: {} messages waiting, it does not read them", outbox_.size());
        close();
        return;
    }
    const bool idle = outbox_.empty();
    outbox_.push_back(encode_delimited(response));
    if (idle) write();
}

void ControlServer::Session::write() {
    auto self = shared_from_this();
    asio::async_write(socket_, asio::buffer(outbox_.front()), [this, self](const boost::system::error_code& ec, std::size_t) {
        if (ec || closed_) {
            close();
            return;
        }
        outbox_.pop_front();
        if (!outbox_.empty()) {
            write();
        } else if (closing_) {
            close();
        }
    });
}

}  // namespace ecpair::control
