#pragma once
// Waiting for a file descriptor without spinning: every blocking receive of a
// link is "try, then sleep in the kernel until the fd says there may be more".

#include <chrono>
#include <string>

#include "ecpair/common/expected.hpp"

namespace ecpair::link::detail {

// Blocks until `fd` is readable (or reports an error condition, which the
// caller's next read consumes) or `timeout` has passed. True when the fd is
// ready, false on timeout; an error names the system's reason.
Expected<bool, std::string> wait_readable(int fd, std::chrono::nanoseconds timeout);

}  // namespace ecpair::link::detail
