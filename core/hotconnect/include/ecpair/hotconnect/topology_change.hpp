#pragma once
// The Hot-Connect state machine of one topology change (hot-connect.md §3,
// §4), as an enum and a transition function; HotConnect runs the work of
// each state and feeds the outcome back in.
//
//   Idle --detected--> Settling --settled--> Scanning
//   Settling --timeout--> Idle                  (the bus kept changing)
//   Scanning --nothing new--> Closing            (groups gone, mismatches reported)
//   Scanning --new groups--> BringingUp          automatic: to the master state
//                        --> PreparingPreop      manual, PREOP: through INIT to PREOP first
//                        --> AwaitingAccept      manual, no reset: as they are
//   PreparingPreop --brought up--> AwaitingAccept
//   AwaitingAccept --accepted--> BringingUp
//   AwaitingAccept --detected--> Settling        (a new change: scan again)
//   BringingUp --brought up--> Closing           (failures are in the result)
//   Closing --closed--> Idle                     (border close done, "topology change done")
//   any --scan failed / cancelled--> Idle
// A change detected while a group is being brought up waits until it is
// done (the next change starts from Idle).

#include <cstdint>
#include <optional>
#include <string_view>

namespace ecpair::hotconnect {

enum class HotConnectMode : std::uint8_t { Automatic, ManualPreop, ManualNoReset };
std::string_view to_string(HotConnectMode mode);

enum class ChangeState : std::uint8_t { Idle, Settling, Scanning, PreparingPreop, AwaitingAccept, BringingUp, Closing };
std::string_view to_string(ChangeState state);

enum class ChangeInput : std::uint8_t {
    Detected,     // the cycle, the periodic check or an operator (force) says the bus changed
    Settled,      // the slave count held still
    Timeout,      // ... not within the detection timeout
    NothingNew,   // the scan found no group to bring up
    NewGroups,    // the scan found groups to bring up
    BroughtUp,    // the bring-up ended (well or not)
    Accepted,     // the operator's accept
    Closed,       // border close done (or not wanted)
    ScanFailed,
    Cancelled,    // the master stopped or became INACTIVE
};
std::string_view to_string(ChangeInput input);

// nullopt: the input means nothing in that state (it is ignored).
std::optional<ChangeState> next_change_state(ChangeState from, ChangeInput input, HotConnectMode mode);

}  // namespace ecpair::hotconnect
