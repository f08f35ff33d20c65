// The listening side of the operator socket; each client is a Session
// (control_session.cpp).

#include "ecpair/control/control_server.hpp"

#include <grp.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cstring>
#include <deque>
#include <filesystem>

#include <fmt/format.h>

#include "ecpair/common/log.hpp"
#include "control_session.hpp"

namespace ecpair::control {

namespace asio = boost::asio;
using stream_protocol = asio::local::stream_protocol;

ControlServer::ControlServer(asio::io_context& io, ControlHandler& handler, SocketSettings settings)
    : io_(io), handler_(handler), settings_(std::move(settings)), acceptor_(io), accept_pause_(io) {}

ControlServer::~ControlServer() {
    boost::system::error_code ignored;
    acceptor_.close(ignored);
    std::error_code fs_ignored;
    if (!settings_.path.empty()) std::filesystem::remove(settings_.path, fs_ignored);
}

Expected<void, std::string> ControlServer::open() {
    const std::filesystem::path path(settings_.path);
    std::error_code fs_error;
    if (path.has_parent_path()) std::filesystem::create_directories(path.parent_path(), fs_error);
    gid_t group_id = static_cast<gid_t>(-1);
    if (!settings_.group.empty()) {
        const group* g = ::getgrnam(settings_.group.c_str());
        if (g == nullptr) return unexpected(fmt::format("control.group: no group named '{}'", settings_.group));
        group_id = g->gr_gid;
    }
    if (std::filesystem::exists(path)) {
        // A socket nobody answers on is left over from a crash: replace it.
        stream_protocol::socket probe(io_);
        boost::system::error_code connect_error;
        probe.connect(stream_protocol::endpoint(settings_.path), connect_error);
        if (!connect_error) return unexpected(fmt::format("{}: another daemon is listening there", settings_.path));
        std::filesystem::remove(path, fs_error);
    }
    boost::system::error_code ec;
    acceptor_.open(stream_protocol(), ec);
    // Linux creates the socket file with the socket's own mode (less the
    // umask): owner-only until the group is right, so nobody else can
    // connect in between.
    if (!ec && ::fchmod(acceptor_.native_handle(), settings_.mode & 0700) != 0) {
        return unexpected(fmt::format("{}: fchmod: {}", settings_.path, std::strerror(errno)));
    }
    if (!ec) acceptor_.bind(stream_protocol::endpoint(settings_.path), ec);
    if (!ec) acceptor_.listen(asio::socket_base::max_listen_connections, ec);
    if (ec) return unexpected(fmt::format("{}: {}", settings_.path, ec.message()));
    if (group_id != static_cast<gid_t>(-1) && ::chown(settings_.path.c_str(), static_cast<uid_t>(-1), group_id) != 0) {
        return unexpected(fmt::format("{}: chown to group {}: {}", settings_.path, settings_.group, std::strerror(errno)));
    }
    if (::chmod(settings_.path.c_str(), settings_.mode) != 0) {
        return unexpected(fmt::format("{}: chmod {:o}: {}", settings_.path, settings_.mode, std::strerror(errno)));
    }
    accept();
    logger("control")->info("operator socket {} (mode {:o}{}; request timeout {} ms, at most {} clients)", settings_.path,
                            settings_.mode, settings_.group.empty() ? "" : ", group " + settings_.group,
                            settings_.request_timeout.count(), settings_.max_clients);
    return {};
}

void ControlServer::accept() {
    acceptor_.async_accept([this](const boost::system::error_code& ec, stream_protocol::socket socket) {
        if (ec == asio::error::operation_aborted || !acceptor_.is_open()) return;  // closed
        if (ec) {
            // Out of descriptors (EMFILE, ENFILE) or memory: the client waits in the backlog.
            logger("control")->warn("operator socket: accept failed ({}); trying again shortly", ec.message());
            accept_later();
            return;
        }
        std::erase_if(sessions_, [](const std::weak_ptr<Session>& s) { return s.expired(); });
        auto session = std::make_shared<Session>(std::move(socket), *this);
        if (sessions_.size() >= settings_.max_clients) {
            ++counters_.refused_busy;
            session->refuse(fmt::format("busy: {} operator clients are connected already (control.max_clients)",
                                        sessions_.size()));
        } else {
            sessions_.push_back(session);
            session->start();
        }
        accept();
    });
}

void ControlServer::accept_later() {
    accept_pause_.expires_after(std::chrono::milliseconds(100));
    accept_pause_.async_wait([this](const boost::system::error_code& ec) {
        if (!ec) accept();
    });
}

void ControlServer::publish(const EventMessage& event) {
    backlog_.push_back(event);
    if (backlog_.size() > kBacklog) backlog_.pop_front();
    Response response;
    response.set_ok(true);
    *response.mutable_event() = event;
    for (const auto& weak : sessions_) {
        if (auto session = weak.lock(); session && session->watching()) session->send(response);
    }
}

void ControlServer::fill_status(OperatorSocketStatus& out) const {
    out.set_clients(static_cast<std::uint32_t>(clients()));
    out.set_max_clients(static_cast<std::uint32_t>(settings_.max_clients));
    out.set_request_timeout_ms(static_cast<std::uint32_t>(settings_.request_timeout.count()));
    out.set_refused_busy(counters_.refused_busy);
    out.set_timed_out(counters_.timed_out);
    out.set_malformed(counters_.malformed);
    out.set_slow_watchers(counters_.slow_watchers);
}

std::size_t ControlServer::clients() const {
    return static_cast<std::size_t>(
        std::count_if(sessions_.begin(), sessions_.end(), [](const std::weak_ptr<Session>& s) { return !s.expired(); }));
}

}  // namespace ecpair::control
