#pragma once
// Cyclic Master Red Frames (design.md §3; the bytes in docs/WIRE_FORMAT.md).
//
// Every cycle the ACTIVE sends, after its cyclic slave frames and on MAIN and
// RED, what its standby needs to take over without a hiccup: a HEADER (format
// version, cycle counter, master state, redundancy flags, the pair
// parameters and their fingerprint), the slave state image, the merged
// shadow inputs of the last cycle, its master process data for the partner,
// and room for the partner's master process data.
//
//   ACTIVE   CmfWriter::write(content, sender)       cmf_writer.hpp
//   INACTIVE process_as_inactive(frame, pd_in)       cmf_inactive.hpp   (as it forwards)
//            CmfAssembler::feed(datagram)            cmf_assembler.hpp  (the mirror)
//   ACTIVE   CmfAssembler::feed(returned datagram)   (the partner's MASTER_PD_IN and WKCs)
//
// The format types (segment header, HEADER, slave entries, layout and plan)
// are in cmf_format.hpp.

#include "ecpair/redundancy/cmf_assembler.hpp"
#include "ecpair/redundancy/cmf_format.hpp"
#include "ecpair/redundancy/cmf_inactive.hpp"
#include "ecpair/redundancy/cmf_writer.hpp"
