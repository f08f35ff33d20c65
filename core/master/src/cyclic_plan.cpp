#include "ecpair/master/cyclic_plan.hpp"

#include <algorithm>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "ecpair/common/log.hpp"
#include "ecpair/wire/constants.hpp"
#include "ecpair/wire/datagram.hpp"
#include "ecpair/wire/esc_registers.hpp"
#include "ecpair/wire/fmmu_config.hpp"

namespace ecpair::master {
namespace {

constexpr std::uint32_t kFrameImageFirstDatagram = wire::kEthernetHeaderSize + wire::kEcatHeaderSize;

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

}  // namespace

std::string_view to_string(OffsetConvention convention) {
    return convention == OffsetConvention::Compact ? "compact image" : "frame image";
}

FmmuDirections fmmu_directions(const eni::EniConfig& eni, std::uint32_t address, std::size_t length) {
    FmmuDirections directions;
    for (const auto& slave : eni.slaves) {
        bool reads = false;
        bool writes = false;
        for (const auto& cmd : slave.init_cmds) {
            if (cmd.command != wire::Command::Fpwr && cmd.command != wire::Command::Apwr) continue;
            const std::uint32_t end = static_cast<std::uint32_t>(cmd.ado) + static_cast<std::uint32_t>(cmd.data.size());
            if (cmd.ado < wire::reg::kFmmuBase || cmd.ado >= wire::reg::kSmBase) continue;
            // Whole 16-byte FMMU records written by this command.
            for (std::uint32_t at = cmd.ado; at + wire::FmmuConfig::kSize <= end; at += wire::FmmuConfig::kSize) {
                if ((at - wire::reg::kFmmuBase) % wire::FmmuConfig::kSize != 0) break;
                const auto fmmu = wire::FmmuConfig::decode(
                    ConstBytes(cmd.data).subspan(at - cmd.ado, wire::FmmuConfig::kSize));
                if (!fmmu.active || !fmmu.overlaps(address, length)) continue;
                reads = reads || fmmu.read;
                writes = writes || fmmu.write;
            }
        }
        directions.readers = static_cast<std::uint16_t>(directions.readers + (reads ? 1 : 0));
        directions.writers = static_cast<std::uint16_t>(directions.writers + (writes ? 1 : 0));
    }
    return directions;
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

            if (cmd.command == wire::Command::Lrw && options.cable_redundancy && options.split_lrw) {
                const auto directions = fmmu_directions(eni, cmd.logical_address, cmd.data_length);
                if (cmd.expected_wkc && *cmd.expected_wkc != 2 * directions.writers + directions.readers) {
                    logger("master")->warn(
                        "{}: LRW at line {} expects WKC {}, but the FMMUs give {} writer(s) and {} reader(s)",
                        eni.source_path, cmd.source_line, *cmd.expected_wkc, directions.writers, directions.readers);
                }
                PlannedDatagram write = d;
                write.command = wire::Command::Lwr;
                write.input_offset.reset();
                write.expected_wkc = directions.writers;
                write.split_from_lrw = true;
                PlannedDatagram read = d;
                read.command = wire::Command::Lrd;
                read.output_offset.reset();
                read.expected_wkc = directions.readers;
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
