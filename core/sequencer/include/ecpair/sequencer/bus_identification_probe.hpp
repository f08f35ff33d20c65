#pragma once
// The identification values the topology match asks for, read from the
// bus (hot-connect.md §9) at a slave's position, each at most once:
//   explicit device ID  ID request in AL control, the ID from 0x0134 once
//                       AL status bit 5 shows it (read_explicit_device_id);
//   register            a 16-bit read at the identification Ado;
//   IdentifyCmds        the group head's IdentifyCmds run like InitCmds,
//                       their auto-increment addresses moved to the position.
// Station aliases come with the scan; input words are read in SAFEOP by the
// bring-up, not here.

#include <cstdint>
#include <map>
#include <optional>
#include <stop_token>
#include <utility>

#include "ecpair/bus/bus_access.hpp"
#include "ecpair/bus/topology_match.hpp"
#include "ecpair/eni/model.hpp"
#include "ecpair/sequencer/clock.hpp"

namespace ecpair::sequencer {

class BusIdentificationProbe final : public bus::IdentificationProbe {
public:
    static constexpr std::chrono::milliseconds kExplicitIdTimeout{500};

    BusIdentificationProbe(bus::BusAccess& bus, Clock& clock, const eni::EniConfig& eni, std::stop_token stop = {})
        : bus_(bus), clock_(clock), eni_(eni), stop_(std::move(stop)) {}

    std::optional<std::uint16_t> read(std::uint16_t position, const eni::IdentificationSpec& spec) override;
    bool identify_cmds_pass(std::uint16_t position, std::size_t head) override;

    // The explicit device IDs read so far, by position (for reports).
    const std::map<std::uint16_t, std::optional<std::uint16_t>>& explicit_ids() const { return explicit_ids_; }

private:
    bus::BusAccess& bus_;
    Clock& clock_;
    const eni::EniConfig& eni_;
    std::stop_token stop_;
    std::map<std::uint16_t, std::optional<std::uint16_t>> explicit_ids_;
    std::map<std::pair<std::uint16_t, std::uint16_t>, std::optional<std::uint16_t>> registers_;
    std::map<std::pair<std::uint16_t, std::size_t>, bool> identify_cmds_;
};

}  // namespace ecpair::sequencer
