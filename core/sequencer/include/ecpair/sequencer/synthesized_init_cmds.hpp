#pragma once
// ESC InitCmds for a slave whose ENI entry has none (Advantech's files),
// made from what the entry does say. Per transition:
//   IP   request INIT with error acknowledge (APWR 0x0120 = 0x11) and check it,
//        set the station address (APWR 0x0010 = PhysAddr), clear SM0/SM1 and
//        write them from the mailbox areas (mailbox_channel_of; control bytes
//        from Sm0/Sm1 or 0x26/0x22), request PREOP and check it;
//   PS   write the process-data SyncManagers (Outputs/Inputs) the ENI lists
//        with a start address; the length is the bits of the PDOs assigned to
//        the SM, else its DefaultSize; request SAFEOP and check it;
//   SO   request OP and check it;
//   OS, OP, SP, OI, SI, PI: request the lower state and check it.
// Position-addressed commands carry the slave's auto-increment address as the
// ENI would write it (0, 0xFFFF, ...), so absent slaves shift them the same
// way. FMMUs are not made up: the files that need this have no logical
// addresses to map.

#include <vector>

#include "ecpair/eni/model.hpp"

namespace ecpair::sequencer {

std::vector<eni::EcatCmd> synthesize_esc_init_cmds(const eni::Slave& slave, eni::Transition transition);

}  // namespace ecpair::sequencer
