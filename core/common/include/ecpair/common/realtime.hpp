#pragma once
// Asks for SCHED_FIFO for the calling thread. Time-critical threads (the
// cycle, the receive threads, ecsim's loop) use it; where the system does
// not permit it they say so once and go on with normal priority.

#include <string>

namespace ecpair {

// priority 0 asks for nothing and returns false. `who` names the thread in the log.
bool request_realtime(int priority, const std::string& who);

}  // namespace ecpair
