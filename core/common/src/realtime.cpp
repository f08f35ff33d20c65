#include "ecpair/common/realtime.hpp"

#include <pthread.h>
#include <sched.h>

#include <cstring>

#include "ecpair/common/log.hpp"

namespace ecpair {

bool request_realtime(int priority, const std::string& who) {
    if (priority <= 0) return false;
    sched_param param{};
    param.sched_priority = priority;
    const int rc = pthread_setschedparam(pthread_self(), SCHED_FIFO, &param);
    if (rc == 0) {
        logger("realtime")->info("{} runs with SCHED_FIFO priority {}", who, priority);
        return true;
    }
    logger("realtime")->warn("{}: real-time scheduling not permitted ({}), running with normal priority", who,
                             std::strerror(rc));
    return false;
}

}  // namespace ecpair
