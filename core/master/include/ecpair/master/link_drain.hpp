#pragma once
// Reading the frames that wait on a link, on the caller's thread: a cycle
// that takes its links' frames once a cycle instead of having a receive
// thread woken for every frame (MasterOptions::receive_in_cycle, and a pair
// member that does not forward in user space).

#include <cstddef>
#include <functional>

#include "ecpair/common/bytes.hpp"
#include "ecpair/link/link.hpp"

namespace ecpair::master {

using FrameHandler = std::function<void(ConstBytes frame, link::Clock::time_point arrived_at)>;

// Hands each waiting frame to `handler`, at most `limit` of them (the rest
// wait for the next call, so a flood cannot hold the caller), with when it
// arrived: the link's capture time (a PcapLink's is the kernel's receive
// timestamp) on the steady clock, so a frame read late still says when it
// came. Stops at a link error (a link going down answers so for a while;
// logged at debug). Returns how many frames it handed over.
std::size_t drain_link(link::Link& link, Bytes buffer, std::size_t limit, const FrameHandler& handler);

}  // namespace ecpair::master
