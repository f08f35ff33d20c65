#include "cycle_batches.hpp"

namespace ecpair::master::detail {

CycleBatches::CycleBatches(std::size_t copies_per_link)
    : links_{PerLink(copies_per_link), PerLink(copies_per_link)} {}

void CycleBatches::add(LinkRole role, ConstBytes frame, std::size_t owner) {
    PerLink& batch = of(role);
    if (!batch.frames.append(frame)) return;  // full or oversized: the caller checks full(); frames fit a slot
    batch.owners.push_back(owner);
}

}  // namespace ecpair::master::detail
