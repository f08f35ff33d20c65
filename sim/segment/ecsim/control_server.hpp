#pragma once
// The Unix stream socket ecsim listens on for control requests. It does not
// run a loop of its own: the owner polls the descriptors it lists
// (append_poll_fds) and hands the results back (on_poll), so one thread
// serves frames and control alike. Each complete request line goes to the
// handler, whose answer goes back with a newline. A client sending a line
// longer than the protocol allows gets an error and is disconnected.

#include <poll.h>

#include <cstddef>
#include <filesystem>
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "ecpair/common/expected.hpp"

namespace ecpair::ecsim {

struct ControlServerError {
    std::string message;  // names the path and the system's reason
};

class ControlServer {
public:
    using Handler = std::function<std::string(std::string_view request_line)>;

    // Creates the socket's directory if needed, replaces a stale socket file
    // (refuses when another process still answers on it), binds and listens.
    static Expected<std::unique_ptr<ControlServer>, ControlServerError> listen(const std::filesystem::path& path,
                                                                               Handler handler);
    ~ControlServer();  // closes every connection and removes the socket file
    ControlServer(const ControlServer&) = delete;
    ControlServer& operator=(const ControlServer&) = delete;

    const std::filesystem::path& path() const { return path_; }

    // Appends the descriptors to wait on; returns how many.
    std::size_t append_poll_fds(std::vector<pollfd>& fds) const;
    // The entries append_poll_fds() added, after poll() filled in revents.
    void on_poll(std::span<const pollfd> fds);

private:
    struct Client;
    ControlServer(std::filesystem::path path, int listen_fd, Handler handler);
    void accept_clients();
    // Reads what the client sent and answers complete lines; false: drop it.
    bool serve(Client& client);
    bool flush(Client& client);

    std::filesystem::path path_;
    int listen_fd_;
    Handler handler_;
    std::vector<std::unique_ptr<Client>> clients_;
};

}  // namespace ecpair::ecsim
