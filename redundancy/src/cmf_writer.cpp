// CmfWriter: per cycle, encode the HEADER and the slave entries into buffers
// sized at construction, then walk the plan: for each of its frames, build
// the frame in the sender's buffer with one NOP datagram per part (segment
// header + that piece of its section; MASTER_PD_IN stays zero) and send it.
// The plan already says which part goes in which frame, so write() makes no
// decisions of its own and the receiver can check every part against the
// same plan.

#include "ecpair/redundancy/cmf_writer.hpp"

#include <algorithm>

#include <fmt/format.h>

#include "ecpair/wire/frame.hpp"
#include "ecpair/wire/esc_registers.hpp"

namespace ecpair::redundancy {

std::string CmfWriteError::describe() const {
    switch (what) {
        case What::SlaveCount:
            return fmt::format("CMF content has {} slave entries, the layout {}", actual, expected);
        case What::ShadowInputsSize:
            return fmt::format("CMF content has {} shadow input bytes, the layout {}", actual, expected);
        case What::MasterPdOutSize:
            return fmt::format("CMF content has {} master PD out bytes, the layout {}", actual, expected);
        case What::SenderBufferTooSmall:
            return fmt::format("the frame sender's buffer holds {} bytes, a CMF frame needs {}", actual, expected);
    }
    return "CMF write error";
}

CmfWriter::CmfWriter(CmfPlan plan)
    : plan_(std::move(plan)), slave_bytes_(plan_.layout().section_size(CmfKind::SlaveStateImage)) {}

Expected<void, CmfWriteError> CmfWriter::check(const CmfContent& content, std::size_t buffer_size,
                                               std::size_t ethernet_header_size) const {
    using What = CmfWriteError::What;
    const CmfLayout& layout = plan_.layout();
    if (content.slaves.size() != layout.slave_count) {
        return unexpected(CmfWriteError{What::SlaveCount, layout.slave_count, content.slaves.size()});
    }
    if (content.shadow_inputs.size() != layout.shadow_inputs_size) {
        return unexpected(CmfWriteError{What::ShadowInputsSize, layout.shadow_inputs_size, content.shadow_inputs.size()});
    }
    if (content.master_pd_out.size() != layout.parameters.master_pd_out_size) {
        return unexpected(
            CmfWriteError{What::MasterPdOutSize, layout.parameters.master_pd_out_size, content.master_pd_out.size()});
    }
    const std::size_t needed =
        std::max(wire::kMinFrameSize, ethernet_header_size + wire::kEcatHeaderSize + plan_.max_frame_payload());
    if (buffer_size < needed) return unexpected(CmfWriteError{What::SenderBufferTooSmall, needed, buffer_size});
    return {};
}

void CmfWriter::encode_sections(const CmfContent& content) {
    CmfHeader::describe(plan_, content.cycle, content.master_state, content.flags, content.sender).encode(header_bytes_);
    for (std::size_t i = 0; i < content.slaves.size(); ++i) {
        encode_slave_entry(content.slaves[i], Bytes(slave_bytes_).subspan(i * kCmfSlaveEntrySize));
    }
}

ConstBytes CmfWriter::section(const CmfContent& content, CmfKind kind) const {
    switch (kind) {
        case CmfKind::Header: return header_bytes_;
        case CmfKind::SlaveStateImage: return slave_bytes_;
        case CmfKind::ShadowInputs: return content.shadow_inputs;
        case CmfKind::MasterPdOut: return content.master_pd_out;
        case CmfKind::MasterPdIn:
        case CmfKind::StandbyStatus: return {};  // zeros, for the INACTIVE to fill
    }
    return {};
}

Expected<std::size_t, CmfWriteError> CmfWriter::write(const CmfContent& content, master::FrameSender& sender) {
    const wire::EthernetHeader ethernet = sender.ethernet();
    const Bytes buffer = sender.buffer();
    if (auto ok = check(content, buffer.size(), ethernet.size()); !ok) return unexpected(ok.error());
    encode_sections(content);

    const auto parts = plan_.parts();
    const auto part_count = static_cast<std::uint16_t>(parts.size());
    wire::DatagramHeader datagram;
    datagram.command = wire::Command::Nop;
    datagram.address = wire::DatagramHeader::physical(0, wire::reg::kMasterRedAdo);

    std::size_t next = 0;
    for (std::size_t frame = 0; frame < plan_.frame_count(); ++frame) {
        wire::FrameBuilder builder(buffer, ethernet);
        for (; next < parts.size() && parts[next].frame == frame; ++next) {
            const CmfPart& part = parts[next];
            // check() made sure the frame fits: append cannot fail here.
            const auto view = builder.append(datagram, CmfSegmentHeader::kSize + part.length);
            const Bytes data = view->data();
            CmfSegmentHeader{kCmfFormatVersion, part.kind, static_cast<std::uint16_t>(next), part_count, part.offset,
                             static_cast<std::uint32_t>(content.cycle)}
                .encode(data);
            const ConstBytes source = section(content, part.kind);
            if (!source.empty()) {
                const auto piece = source.subspan(part.offset, part.length);
                std::copy(piece.begin(), piece.end(), data.begin() + CmfSegmentHeader::kSize);
            }
        }
        sender.send(static_cast<std::uint16_t>(frame), builder.finish());
    }
    return plan_.frame_count();
}

}  // namespace ecpair::redundancy
