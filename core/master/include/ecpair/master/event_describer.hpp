#pragma once
// Operator text for master events, made on the consumer's side (ecpaird's
// event pump and operator API) from the small Event values the cycle and
// the workers raise. It knows the ENI and the cyclic plan, so it says
// which slave (name, position, station address), which frame (its number,
// the state it was built for, its datagrams) or which acyclic request an
// event is about, and what the master did about it. Kinds it has nothing
// to add to are described by master::describe().

#include <cstdint>
#include <memory>
#include <string>

#include "ecpair/eni/model.hpp"
#include "ecpair/master/cyclic_plan.hpp"
#include "ecpair/master/events.hpp"

namespace ecpair::master {

class EventDescriber {
public:
    // `plan` may be null (frames and datagrams are then named by number
    // only); it must outlive the describer.
    EventDescriber(std::shared_ptr<const eni::EniConfig> eni, const CyclicPlan* plan);

    std::string describe(const Event& event) const;

    // "'Term 2 (EL2008)' (position 2, station 1002)" for the ENI's slave `index` (from 0).
    std::string slave(std::size_t index) const;

private:
    std::string slave_at_position(std::uint32_t position) const;  // 1-based ring position
    std::string datagram(const PlannedDatagram& d) const;
    std::string cyclic_frame(std::uint32_t index, std::uint8_t state) const;
    std::string wkc_error(const Event& e) const;
    std::string lost_frame(const Event& e) const;
    std::string acyclic_target(wire::Command command, std::uint32_t address) const;
    std::string slaves_mapping(std::uint32_t logical, std::size_t length) const;

    std::shared_ptr<const eni::EniConfig> eni_;
    const CyclicPlan* plan_;
};

}  // namespace ecpair::master
