#pragma once
// What the INACTIVE does to a Cyclic Master Red Frame as it forwards it
// (design.md §3): like a slave, it processes the frame in place. It writes
// its INACTIVE->ACTIVE master process data into the MASTER_PD_IN datagrams
// and its standby status into the STANDBY_STATUS datagram, adding 1 to
// their WKC, and adds 2 to the WKC of every datagram it reads (HEADER,
// SLAVE_STATE_IMAGE, SHADOW_INPUTS, MASTER_PD_OUT). The ACTIVE sees from the
// returned WKCs that its partner is there and has read the CMF.

#include "ecpair/common/bytes.hpp"
#include "ecpair/wire/frame.hpp"

namespace ecpair::redundancy {

inline constexpr std::uint16_t kCmfReadWkcIncrement = 2;
inline constexpr std::uint16_t kCmfWriteWkcIncrement = 1;

// Processes every CMF datagram of `frame` whose segment header this format
// version reads; any other datagram is left alone. MASTER_PD_IN datagrams
// receive master_pd_in[offset, offset + length), STANDBY_STATUS datagrams
// standby_status likewise; bytes beyond the end of what is given stay as the
// ACTIVE sent them. Returns whether the frame was a CMF, i.e. whether a
// datagram was processed.
bool process_as_inactive(wire::FrameView& frame, ConstBytes master_pd_in, ConstBytes standby_status);

}  // namespace ecpair::redundancy
