#include "open_file_limit.hpp"

#include <sys/resource.h>

#include <algorithm>

#include "ecpair/common/log.hpp"

namespace ecpair::daemon {

std::uint64_t raise_open_file_limit(std::uint64_t wanted) {
    rlimit limit{};
    if (::getrlimit(RLIMIT_NOFILE, &limit) != 0) return 0;
    const rlim_t target = std::min<rlim_t>(limit.rlim_max, static_cast<rlim_t>(wanted));
    if (target > limit.rlim_cur) {
        limit.rlim_cur = target;
        if (::setrlimit(RLIMIT_NOFILE, &limit) != 0) ::getrlimit(RLIMIT_NOFILE, &limit);
    }
    if (limit.rlim_cur < wanted) {
        logger("ecpaird")->warn("open files limited to {} (wanted {}): raise LimitNOFILE", limit.rlim_cur, wanted);
    }
    return limit.rlim_cur;
}

}  // namespace ecpair::daemon
