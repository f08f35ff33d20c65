#pragma once
// How much each configured slave adds to the working counter of each
// cyclic datagram, so that the expected WKCs can follow the slaves that are
// on the bus (hot-connect.md §1: "correct the expected WKCs"):
//   broadcast (BRD, BWR, BRW)  every slave that answers: 1, 1, 3 -- counted
//                              from the slaves the scan found (configured or
//                              not: an unknown slave answers a BRD too);
//   logical (LRD, LWR, LRW)    the slaves whose FMMU InitCmds map the range:
//                              LRD 1 per reader, LWR 1 per writer, LRW both
//                              (read 1 + write 2) -- once they run (SAFEOP);
//   FPxx / APxx                the slave addressed: 1 (RW: 3);
//   anything else              left as the ENI says.
// expected() subtracts what is missing from the ENI's <Cnt>; datagrams
// without a <Cnt> stay unchecked.

#include <cstdint>
#include <optional>
#include <vector>

#include "ecpair/eni/model.hpp"
#include "ecpair/master/cyclic_plan.hpp"

namespace ecpair::hotconnect {

enum class ContributionKind : std::uint8_t { Broadcast, Logical, Addressed, Fixed };

struct DatagramContribution {
    ContributionKind kind = ContributionKind::Fixed;
    std::optional<std::uint16_t> eni_expected;  // <Cnt> as planned
    std::uint16_t per_slave = 0;                // Broadcast: what each answering slave adds
    std::vector<std::uint16_t> by_slave;        // Logical/Addressed: per EniConfig::slaves index
};

// What the expected WKCs are computed from.
struct BusCount {
    std::vector<bool> counted;  // per ENI slave: on the bus and exchanging process data
    std::vector<bool> present;  // per ENI slave: on the bus (answers FPxx)
    std::uint16_t answering = 0;  // slaves that answer a broadcast (all found by the scan)
};

class WkcContributions {
public:
    static WkcContributions of(const eni::EniConfig& eni, const master::CyclicPlan& plan);

    // Flat, in CyclicExchange numbering.
    const std::vector<DatagramContribution>& datagrams() const { return datagrams_; }
    std::vector<std::optional<std::uint16_t>> expected(const BusCount& bus) const;

private:
    std::vector<DatagramContribution> datagrams_;
    std::size_t configured_ = 0;
};

}  // namespace ecpair::hotconnect
