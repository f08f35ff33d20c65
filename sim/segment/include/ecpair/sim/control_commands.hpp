#pragma once
// What ecsim's control requests do to a segment, and the status report.
// Each call returns the complete response line (without the newline):
// "ok ..." or "error: ...".

#include <string>
#include <string_view>

#include "ecpair/sim/control_protocol.hpp"
#include "ecpair/sim/segment.hpp"

namespace ecpair::sim {

std::string execute_control_request(Segment& segment, const ControlRequest& request);

// Parses and executes one request line.
std::string handle_control_line(Segment& segment, std::string_view line);

// The `status` response:
//   ok slaves=N main=up red=up in=MAIN:12,RED:12 out=MAIN:12,RED:12
//      destroyed=0 lost_no_link=0 lost_closed_port=0 non_ecat_dropped=0
//      unprocessable=0 hop_limit=0 broken=none
//      | 1 name="EK1100" vendor=0x00000002 product=0x044c2c52 addr=0x03e9 alias=0x0000
//        al=OP powered=yes unknown=no ports=0:up/open,1:up/open
//      | 2 ...
// (one line; `broken` lists the k of every cut `link after slave k`.)
std::string format_status(const Segment& segment);

}  // namespace ecpair::sim
