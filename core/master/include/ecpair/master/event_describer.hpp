#pragma once
// Operator text for events, made on the consumer's side (ecpaird's event
// pump and operator API) from the small Event values the cycle and the
// workers raise. Each kind describes itself (EventType::describe, in the
// folder of the layer that owns it); the describer puts the real cycle in
// front and lends every description what it knows of the ENI and the cyclic
// plan: which slave (name, position, station address), which frame (its
// number, the state it was built for, its datagrams) or which acyclic
// request an event is about. A fault that repeats is described from the
// EventReport: how many, of which subjects, in which cycles.

#include <cstdint>
#include <memory>
#include <string>

#include "ecpair/eni/model.hpp"
#include "ecpair/master/cyclic_plan.hpp"
#include "ecpair/master/event.hpp"
#include "ecpair/master/event_report.hpp"

namespace ecpair::master {

class EventDescriber {
public:
    // `eni` and `plan` may be null (slaves, frames and datagrams are then
    // named by number only); the plan must outlive the describer.
    EventDescriber(std::shared_ptr<const eni::EniConfig> eni, const CyclicPlan* plan);

    // "cycle 123: line break after slave 2 ...".
    std::string describe(const Event& event) const;
    // A single event as above; a summary or an end with its counts and subjects.
    std::string describe(const EventReport& report) const;

    // ---- for the kinds' descriptions
    // "'Term 2 (EL2008)' (position 2, station 1002)" for the ENI's slave `index` (from 0).
    std::string slave(std::size_t index) const;
    std::string slave_at_position(std::uint32_t position) const;  // 1-based ring position
    std::size_t slave_count() const;
    // "cyclic frame 1 of 2 (OP: BRD 0x0130, LRD 0x01000800 1 B)".
    std::string cyclic_frame(std::uint32_t index, std::uint8_t state) const;
    // The plan's datagram, or null when there is no plan or no such datagram.
    const PlannedDatagram* cyclic_datagram(std::uint32_t frame, std::uint32_t datagram) const;
    // "LRD 0x01000800, 1 bytes, 'inputs', ENI line 120".
    std::string datagram(const PlannedDatagram& d) const;
    // What an acyclic datagram addresses: "'Term 2' (position 2, station 1002), register 0x0130".
    std::string acyclic_target(wire::Command command, std::uint32_t address) const;
    // "; the slaves mapping it: ..." for slaves whose FMMU InitCmds map part of the logical range.
    std::string slaves_mapping(std::uint32_t logical, std::size_t length) const;
    // "; addressed to ..." for a configured station address in the ENI.
    std::string addressed_station(std::uint16_t station) const;

private:
    std::string subjects_text(const EventReport& report) const;

    std::shared_ptr<const eni::EniConfig> eni_;
    const CyclicPlan* plan_;
};

}  // namespace ecpair::master
