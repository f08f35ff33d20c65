#pragma once
// Where each configured slave hangs, as the ENI says (the rules ecsim wires
// a segment by, docs/ENI.md "Topology"):
//   - slave 0 hangs on the master (MAIN);
//   - a slave with a PreviousPort hangs on that port of that slave (the
//     selected entry, else the first);
//   - the head of a floating Hot-Connect group hangs nowhere: it may be
//     plugged in at any free port (see is_floating_head);
//   - any other slave hangs on port B of the slave before it in the file.
// Ports are numbered 0..3 (letters A..D); a frame visits a slave's ports in
// the order 0 -> EPU -> 3 -> 1 -> 2, so children are listed in that order.

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include "ecpair/eni/model.hpp"

namespace ecpair::eni {

inline constexpr int kEscPorts = 4;
// The ports a frame leaves a slave by after its processing unit, in order.
inline constexpr std::array<int, 3> kDownstreamPorts{3, 1, 2};

struct Attachment {
    std::size_t parent = 0;  // EniConfig::slaves index
    int port = 1;            // the parent's port, 0..3
    friend bool operator==(const Attachment&, const Attachment&) = default;
};

// A floating group's head: it heads a Hot-Connect group, names no
// PreviousPort, is not the first slave, and the file places its other slaves
// with PreviousPort (so "no PreviousPort" is a statement, not a line ENI's habit).
bool is_floating_head(const std::vector<Slave>& slaves, std::size_t index);
inline bool is_floating_head(const EniConfig& eni, std::size_t index) { return is_floating_head(eni.slaves, index); }

class EniTopology {
public:
    static EniTopology of(const std::vector<Slave>& slaves);
    static EniTopology of(const EniConfig& eni) { return of(eni.slaves); }

    std::size_t size() const { return attachments_.size(); }
    // nullopt for slave 0 and for floating heads.
    const std::optional<Attachment>& attachment(std::size_t index) const { return attachments_[index]; }
    // The slave configured at `port` of `parent`, if any.
    std::optional<std::size_t> child(std::size_t parent, int port) const;
    bool floating(std::size_t index) const { return floating_[index]; }

private:
    std::vector<std::optional<Attachment>> attachments_;
    std::vector<std::array<std::optional<std::size_t>, kEscPorts>> children_;
    std::vector<bool> floating_;
};

// "A".."D".
char port_letter(int port);

}  // namespace ecpair::eni
