#include "ecpair/master/cyclic_plan.hpp"

#include <algorithm>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "ecpair/wire/constants.hpp"
#include "ecpair/wire/datagram.hpp"
#include "ecpair/wire/esc_registers.hpp"
#include "ecpair/wire/fmmu_config.hpp"

namespace ecpair::master {
namespace {

constexpr std::uint32_t kFrameImageFirstDatagram = wire::kEthernetHeaderSize + wire::kEcatHeaderSize;
constexpr std::uint16_t kProcessRam = 0x1000;  // ESC addresses of process data and mailbox buffers start here

// TwinCAT's frame-image offsets: the first datagram header of the first frame
// sits at 16 and every next one right after the previous datagram.
bool offsets_follow_frame_layout(const std::vector<eni::CyclicFrame>& frames) {
    bool any = false;
    for (std::size_t f = 0; f < frames.size(); ++f) {
        std::optional<std::uint32_t> expected;
        for (const auto& cmd : frames[f].cmds) {
            const auto offset = cmd.input_offset ? cmd.input_offset : cmd.output_offset;
            if (!offset) return false;
            if (!expected) {
                if (f == 0 && *offset != kFrameImageFirstDatagram) return false;
            } else if (*offset != *expected) {
                return false;
            }
            if (cmd.input_offset && cmd.output_offset && *cmd.input_offset != *cmd.output_offset) return false;
            expected = *offset + static_cast<std::uint32_t>(wire::kDatagramOverhead) + cmd.data_length;
            any = true;
        }
    }
    return any;
}

std::uint32_t address_of(const eni::CyclicCmd& cmd) {
    return wire::addressing_of(cmd.command) == wire::Addressing::Logical
               ? cmd.logical_address
               : wire::DatagramHeader::physical(cmd.adp, cmd.ado);
}

std::string describe(const eni::CyclicCmd& cmd) {
    return fmt::format("line {} {} 0x{:08x} ({} bytes{})", cmd.source_line, wire::to_string(cmd.command),
                       address_of(cmd), cmd.data_length,
                       cmd.comment.empty() ? std::string() : fmt::format(", '{}'", cmd.comment));
}

// Lays datagrams into frames of at most the EtherCAT payload size, in order.
std::vector<PlannedFrame> pack(const std::vector<std::vector<PlannedDatagram>>& source_frames) {
    std::vector<PlannedFrame> frames;
    for (const auto& datagrams : source_frames) {
        PlannedFrame current;
        std::size_t used = 0;
        for (const auto& d : datagrams) {
            const std::size_t size = wire::kDatagramOverhead + d.length;
            if (!current.datagrams.empty() && used + size > wire::kMaxEcatPayload) {
                frames.push_back(std::move(current));
                current = {};
                used = 0;
            }
            current.datagrams.push_back(d);
            used += size;
        }
        if (!current.datagrams.empty()) frames.push_back(std::move(current));
    }
    return frames;
}

// Calls `visit(cmd, fmmu)` for every active FMMU record an InitCmd of `slave` writes
// (whole 16-byte records, APWR/FPWR at 0x0600 + 16n) that overlaps [address, address + length).
template <class Visit>
void for_each_fmmu(const eni::Slave& slave, std::uint32_t address, std::size_t length, Visit&& visit) {
    for (const auto& cmd : slave.init_cmds) {
        if (cmd.command != wire::Command::Fpwr && cmd.command != wire::Command::Apwr) continue;
        const std::uint32_t end = static_cast<std::uint32_t>(cmd.ado) + static_cast<std::uint32_t>(cmd.data.size());
        if (cmd.ado < wire::reg::kFmmuBase || cmd.ado >= wire::reg::kSmBase) continue;
        for (std::uint32_t at = cmd.ado; at + wire::FmmuConfig::kSize <= end; at += wire::FmmuConfig::kSize) {
            if ((at - wire::reg::kFmmuBase) % wire::FmmuConfig::kSize != 0) break;
            const auto fmmu =
                wire::FmmuConfig::decode(ConstBytes(cmd.data).subspan(at - cmd.ado, wire::FmmuConfig::kSize));
            if (!fmmu.active || !fmmu.overlaps(address, length)) continue;
            visit(cmd, fmmu);
        }
    }
}

// The state an InitCmd's effect is there in: the lowest state its upward
// transitions lead to (nullopt: it names none).
std::optional<eni::SlaveState> reached_by(const eni::EcatCmd& cmd) {
    std::optional<eni::SlaveState> reached;
    for (std::size_t t = 0; t < eni::kTransitionCount; ++t) {
        const auto transition = static_cast<eni::Transition>(t);
        if (!cmd.transitions.contains(transition)) continue;
        const auto to = eni::to_state(transition);
        if (to == eni::SlaveState::Boot || to <= eni::from_state(transition)) continue;
        if (!reached || to < *reached) reached = to;
    }
    return reached;
}

}  // namespace

std::string_view to_string(OffsetConvention convention) {
    return convention == OffsetConvention::Compact ? "compact image" : "frame image";
}

FmmuDirections fmmu_directions(const eni::EniConfig& eni, std::uint32_t address, std::size_t length) {
    FmmuDirections directions;
    for (const auto& slave : eni.slaves) {
        bool reads = false;
        bool writes = false;
        for_each_fmmu(slave, address, length, [&](const eni::EcatCmd&, const wire::FmmuConfig& fmmu) {
            reads = reads || fmmu.read;
            writes = writes || fmmu.write;
        });
        directions.readers = static_cast<std::uint16_t>(directions.readers + (reads ? 1 : 0));
        directions.writers = static_cast<std::uint16_t>(directions.writers + (writes ? 1 : 0));
    }
    return directions;
}

eni::SlaveState logical_range_valid_from(const eni::EniConfig& eni, std::uint32_t address, std::size_t length) {
    bool mapped = false;
    auto valid_from = eni::SlaveState::Preop;
    for (const auto& slave : eni.slaves) {
        for_each_fmmu(slave, address, length, [&](const eni::EcatCmd& cmd, const wire::FmmuConfig& fmmu) {
            mapped = true;
            const auto state = fmmu.physical_start >= kProcessRam ? eni::SlaveState::Safeop
                                                                  : reached_by(cmd).value_or(eni::SlaveState::Safeop);
            valid_from = std::max(valid_from, state);
        });
    }
    return mapped ? valid_from : eni::SlaveState::Safeop;
}

Expected<CyclicPlan, PlanError> CyclicPlan::build(const eni::EniConfig& eni, const PlanOptions& options) {
    std::vector<eni::CyclicFrame> source;
    for (const auto& cyclic : eni.cyclic) source.insert(source.end(), cyclic.frames.begin(), cyclic.frames.end());

    CyclicPlan plan;
    plan.convention = offsets_follow_frame_layout(source) ? OffsetConvention::FrameImage : OffsetConvention::Compact;
    const std::uint32_t data_shift =
        plan.convention == OffsetConvention::FrameImage ? static_cast<std::uint32_t>(wire::kDatagramHeaderSize) : 0;

    if (options.cable_redundancy && !options.split_lrw) {
        std::vector<std::string> lrw;
        for (const auto& frame : source) {
            for (const auto& cmd : frame.cmds) {
                if (cmd.command == wire::Command::Lrw) lrw.push_back(describe(cmd));
            }
        }
        if (!lrw.empty()) {
            return unexpected(PlanError{fmt::format(
                "{}: cable redundancy cannot use LRW (the unprocessed copy would be ORed into the inputs); "
                "the cyclic frames use LRW in: {}. Set split_lrw to send each LRW as LWR + LRD.",
                eni.source_path, fmt::join(lrw, "; "))});
        }
    }

    std::vector<std::vector<PlannedDatagram>> frames;
    for (const auto& frame : source) {
        std::vector<PlannedDatagram> datagrams;
        for (const auto& cmd : frame.cmds) {
            PlannedDatagram d;
            d.command = cmd.command;
            d.address = address_of(cmd);
            d.length = cmd.data_length;
            d.expected_wkc = cmd.expected_wkc;
            d.states = cmd.states;
            d.comment = cmd.comment;
            d.source_line = cmd.source_line;
            if (wire::command_reads(cmd.command) && cmd.input_offset) d.input_offset = *cmd.input_offset + data_shift;
            if (wire::command_writes(cmd.command) && cmd.output_offset) {
                d.output_offset = *cmd.output_offset + data_shift;
            }
            if (wire::addressing_of(cmd.command) == wire::Addressing::Logical) {
                d.valid_from = logical_range_valid_from(eni, cmd.logical_address, cmd.data_length);
            }

            if (cmd.command == wire::Command::Lrw && options.cable_redundancy && options.split_lrw) {
                const auto directions = fmmu_directions(eni, cmd.logical_address, cmd.data_length);
                const auto derived = 2 * directions.writers + directions.readers;
                if (cmd.expected_wkc && *cmd.expected_wkc != derived) {
                    return unexpected(PlanError{fmt::format(
                        "{}: the LRW at line {} expects WKC {}, but the slaves' FMMU InitCmds map its range "
                        "0x{:08x}+{} for {} writer(s) and {} reader(s) (WKC {}): split into LWR + LRD for cable "
                        "redundancy, its expected WKCs cannot be derived. The ENI's FMMU records do not match its "
                        "cyclic commands; export it again (an encrypted or edited file shows this)",
                        eni.source_path, cmd.source_line, *cmd.expected_wkc, cmd.logical_address, cmd.data_length,
                        directions.writers, directions.readers, derived)});
                }
                // Without a <Cnt> the ENI asks for no check, and neither half gets one.
                const auto expected = [&](std::uint16_t count) {
                    return cmd.expected_wkc ? std::optional<std::uint16_t>(count) : std::nullopt;
                };
                PlannedDatagram write = d;
                write.command = wire::Command::Lwr;
                write.input_offset.reset();
                write.expected_wkc = expected(directions.writers);
                write.split_from_lrw = true;
                PlannedDatagram read = d;
                read.command = wire::Command::Lrd;
                read.output_offset.reset();
                read.expected_wkc = expected(directions.readers);
                read.split_from_lrw = true;
                datagrams.push_back(write);
                datagrams.push_back(read);
                continue;
            }
            datagrams.push_back(d);
        }
        frames.push_back(std::move(datagrams));
    }
    plan.frames = pack(frames);

    for (const auto& frame : plan.frames) {
        for (const auto& d : frame.datagrams) {
            if (d.input_offset) plan.input_image_size = std::max<std::size_t>(plan.input_image_size, *d.input_offset + d.length);
            if (d.output_offset) {
                plan.output_image_size = std::max<std::size_t>(plan.output_image_size, *d.output_offset + d.length);
            }
        }
    }
    return plan;
}

std::size_t CyclicPlan::datagram_count() const {
    std::size_t n = 0;
    for (const auto& f : frames) n += f.datagrams.size();
    return n;
}

}  // namespace ecpair::master
