#pragma once
// Raises this process's soft limit of open files towards its hard limit
// (at most `wanted`): an operator socket with a thousand clients needs more
// than the usual 1024, and the link guard's socket sits at the top of the
// table (LinkGuard). Logs what it got when that is less than wanted.

#include <cstdint>

namespace ecpair::daemon {

std::uint64_t raise_open_file_limit(std::uint64_t wanted);

}  // namespace ecpair::daemon
