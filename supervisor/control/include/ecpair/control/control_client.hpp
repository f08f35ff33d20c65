#pragma once
// The client side of ecpaird's operator socket, for ecpairctl and tests:
// blocking, one connection per call.

#include <chrono>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "ecpair/common/expected.hpp"
#include "ecpair/control.pb.h"

namespace ecpair::control {

struct ClientError {
    std::string message;  // names the socket and what failed
};

// Sends `request` and returns the first response.
Expected<Response, ClientError> call(const std::string& socket_path, const Request& request,
                                     std::chrono::milliseconds timeout = std::chrono::seconds(5));

// Sends `request` and hands every response to `on_response` until it returns
// false, the server closes, or `duration` passes (zero: no limit).
Expected<void, ClientError> stream(const std::string& socket_path, const Request& request,
                                   const std::function<bool(const Response&)>& on_response,
                                   std::chrono::milliseconds duration = std::chrono::milliseconds(0));

namespace detail {
class Connection;
}

// A WatchEvents connection held open, for a program that waits on several
// things at once (ecpairctl watch): poll fd() for POLLIN, then take() what
// arrived.
class EventSubscription {
public:
    static Expected<EventSubscription, ClientError> open(const std::string& socket_path);
    EventSubscription(EventSubscription&&) noexcept;
    EventSubscription& operator=(EventSubscription&&) noexcept;
    ~EventSubscription();

    int fd() const;
    // Every response that arrived, without waiting (possibly none); an error
    // when the daemon closed the connection.
    Expected<std::vector<Response>, ClientError> take();

private:
    explicit EventSubscription(std::unique_ptr<detail::Connection> connection);
    std::unique_ptr<detail::Connection> connection_;
};

}  // namespace ecpair::control
