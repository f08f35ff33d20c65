#include "ecpair/wire/coe.hpp"

#include <algorithm>

namespace ecpair::wire {
namespace {

constexpr std::size_t kSegmentMinData = 7;

std::uint8_t specifier(SdoCommand command, bool is_response) {
    // Requests: 0 download segment, 1 download, 2 upload, 3 upload segment.
    // Responses: 0 upload segment, 1 download segment, 2 upload, 3 download.
    switch (command) {
        case SdoCommand::DownloadSegment: return is_response ? 1 : 0;
        case SdoCommand::Download: return is_response ? 3 : 1;
        case SdoCommand::Upload: return 2;
        case SdoCommand::UploadSegment: return is_response ? 0 : 3;
        case SdoCommand::Abort: return 4;
    }
    return 4;
}

std::optional<SdoCommand> command_of(std::uint8_t cs, bool is_response) {
    switch (cs) {
        case 0: return is_response ? SdoCommand::UploadSegment : SdoCommand::DownloadSegment;
        case 1: return is_response ? SdoCommand::DownloadSegment : SdoCommand::Download;
        case 2: return SdoCommand::Upload;
        case 3: return is_response ? SdoCommand::Download : SdoCommand::UploadSegment;
        case 4: return SdoCommand::Abort;
        default: return std::nullopt;
    }
}

bool is_segment(SdoCommand c) { return c == SdoCommand::DownloadSegment || c == SdoCommand::UploadSegment; }

// Whether this message carries data after its 8-byte header (a normal transfer).
bool carries_normal_data(const SdoMessage& m) {
    const bool data_direction = (m.command == SdoCommand::Download && !m.is_response) ||
                                (m.command == SdoCommand::Upload && m.is_response);
    return data_direction && !m.expedited;
}

bool carries_expedited_data(const SdoMessage& m) {
    const bool data_direction = (m.command == SdoCommand::Download && !m.is_response) ||
                                (m.command == SdoCommand::Upload && m.is_response);
    return data_direction && m.expedited;
}

// Segment messages that carry data (download request, upload response).
bool segment_carries_data(const SdoMessage& m) {
    return (m.command == SdoCommand::DownloadSegment && !m.is_response) ||
           (m.command == SdoCommand::UploadSegment && m.is_response);
}

}  // namespace

void CoeHeader::encode(Bytes out) const {
    store_le<std::uint16_t>(out, 0,
                            static_cast<std::uint16_t>((number & 0x01FF) | (static_cast<unsigned>(service) << 12)));
}

std::optional<CoeHeader> CoeHeader::decode(ConstBytes in) {
    if (in.size() < kSize) return std::nullopt;
    const auto word = load_le<std::uint16_t>(in, 0);
    return CoeHeader{static_cast<std::uint16_t>(word & 0x01FF), static_cast<CoeService>(word >> 12)};
}

std::size_t SdoMessage::encoded_size() const {
    if (is_segment(command)) return kSegmentHeader + (segment_carries_data(*this) ? std::max(data.size(), kSegmentMinData) : kSegmentMinData);
    if (carries_normal_data(*this)) return kHeaderSize + data.size();
    return kHeaderSize;
}

void SdoMessage::encode(Bytes out) const {
    const std::size_t size = encoded_size();
    std::fill_n(out.begin(), size, std::uint8_t{0});
    std::uint8_t cs = static_cast<std::uint8_t>(specifier(command, is_response) << 5);
    if (is_segment(command)) {
        if (toggle) cs |= 0x10;
        if (segment_carries_data(*this)) {
            const std::size_t unused = data.size() < kSegmentMinData ? kSegmentMinData - data.size() : 0;
            cs = static_cast<std::uint8_t>(cs | (unused << 1));
            if (last_segment) cs |= 0x01;
            std::copy(data.begin(), data.end(), out.begin() + 1);
        }
        out[0] = cs;
        return;
    }
    if (command == SdoCommand::Abort) {
        out[0] = 0x80;
        store_le<std::uint16_t>(out, 1, index);
        out[3] = subindex;
        store_le<std::uint32_t>(out, 4, complete_size);
        return;
    }
    if (complete_access) cs |= 0x10;
    if (carries_expedited_data(*this)) {
        const std::size_t n = std::min<std::size_t>(data.size(), 4);
        cs = static_cast<std::uint8_t>(cs | ((4 - n) << 2) | 0x02 | 0x01);
        std::copy_n(data.begin(), n, out.begin() + 4);
    } else if (carries_normal_data(*this)) {
        cs |= 0x01;  // size indicated
        store_le<std::uint32_t>(out, 4, complete_size);
        std::copy(data.begin(), data.end(), out.begin() + kHeaderSize);
    }
    out[0] = cs;
    store_le<std::uint16_t>(out, 1, index);
    out[3] = subindex;
}

std::optional<SdoMessage> SdoMessage::decode(ConstBytes in, bool is_response) {
    if (in.empty()) return std::nullopt;
    const auto command = command_of(static_cast<std::uint8_t>(in[0] >> 5), is_response);
    if (!command) return std::nullopt;
    SdoMessage m;
    m.command = *command;
    m.is_response = is_response;
    const std::uint8_t cs = in[0];
    if (is_segment(m.command)) {
        if (in.size() < kSegmentHeader + kSegmentMinData) return std::nullopt;
        m.toggle = (cs & 0x10) != 0;
        if (segment_carries_data(m)) {
            m.last_segment = (cs & 0x01) != 0;
            const std::size_t carried = in.size() - kSegmentHeader;
            const std::size_t unused = (cs >> 1) & 0x07;
            // "unused" only shortens a minimal 7-byte segment.
            const std::size_t length = carried == kSegmentMinData ? kSegmentMinData - unused : carried;
            m.data.assign(in.begin() + 1, in.begin() + 1 + static_cast<std::ptrdiff_t>(length));
        }
        return m;
    }
    if (in.size() < kHeaderSize) return std::nullopt;
    m.index = load_le<std::uint16_t>(in, 1);
    m.subindex = in[3];
    if (m.command == SdoCommand::Abort) {
        m.complete_size = load_le<std::uint32_t>(in, 4);
        return m;
    }
    m.complete_access = (cs & 0x10) != 0;
    m.expedited = (cs & 0x02) != 0;
    m.size_indicated = (cs & 0x01) != 0;
    if (carries_expedited_data(m)) {
        const std::size_t n = m.size_indicated ? 4 - ((cs >> 2) & 0x03) : 4;
        m.data.assign(in.begin() + 4, in.begin() + 4 + static_cast<std::ptrdiff_t>(n));
    } else if (carries_normal_data(m)) {
        m.complete_size = load_le<std::uint32_t>(in, 4);
        m.data.assign(in.begin() + kHeaderSize, in.end());
        // A first message never carries more than the announced total.
        if (m.data.size() > m.complete_size) m.data.resize(m.complete_size);
    }
    return m;
}

SdoMessage SdoMessage::abort(std::uint16_t index, std::uint8_t subindex, std::uint32_t code) {
    SdoMessage m;
    m.command = SdoCommand::Abort;
    m.index = index;
    m.subindex = subindex;
    m.complete_size = code;
    return m;
}

void CoeEmergency::encode(Bytes out) const {
    store_le<std::uint16_t>(out, 0, error_code);
    out[2] = error_register;
    std::copy(data.begin(), data.end(), out.begin() + 3);
}

std::optional<CoeEmergency> CoeEmergency::decode(ConstBytes in) {
    if (in.size() < kSize) return std::nullopt;
    CoeEmergency e;
    e.error_code = load_le<std::uint16_t>(in, 0);
    e.error_register = in[2];
    std::copy_n(in.begin() + 3, e.data.size(), e.data.begin());
    return e;
}

std::string_view emergency_error_class(std::uint16_t error_code) {
    // ETG.1000.6 adds the EtherCAT state machine's own codes to CiA 301's classes.
    if (error_code == 0xA000) return "PREOP to SAFEOP transition failed";
    if (error_code == 0xA001) return "SAFEOP to OP transition failed";
    switch (error_code >> 12) {
        case 0x0: return error_code == 0 ? "error reset or no error" : "unknown class";
        case 0x1: return "generic error";
        case 0x2: return "current";
        case 0x3: return "voltage";
        case 0x4: return "temperature";
        case 0x5: return "device hardware";
        case 0x6: return "device software";
        case 0x7: return "additional modules";
        case 0x8: return (error_code >> 8) == 0x81 ? "communication" : (error_code >> 8) == 0x82 ? "protocol error"
                                                                                                 : "monitoring";
        case 0x9: return "external error";
        case 0xA: return "EtherCAT state machine";
        case 0xF: return (error_code >> 8) == 0xFF ? "device specific" : "additional functions";
        default: return "unknown class";
    }
}

std::string_view sdo_abort_text(std::uint32_t code) {
    switch (code) {
        case sdo_abort::kToggleBit: return "toggle bit not changed";
        case sdo_abort::kTimeout: return "SDO protocol timeout";
        case sdo_abort::kUnknownCommand: return "client/server command specifier not valid or unknown";
        case sdo_abort::kInvalidBlockSize: return "invalid block size";
        case sdo_abort::kInvalidSequenceNumber: return "invalid sequence number";
        case sdo_abort::kCrcError: return "CRC error";
        case sdo_abort::kOutOfMemory: return "out of memory";
        case sdo_abort::kUnsupportedAccess: return "unsupported access to an object";
        case sdo_abort::kWriteOnly: return "attempt to read a write-only object";
        case sdo_abort::kReadOnly: return "attempt to write a read-only object";
        case sdo_abort::kSubindexZeroNotZero: return "subindex cannot be written, SI0 must be 0 for write access";
        case sdo_abort::kCompleteAccessUnsupported: return "SDO complete access not supported";
        case sdo_abort::kObjectDoesNotExist: return "object does not exist in the object dictionary";
        case sdo_abort::kCannotMapObject: return "object cannot be mapped to the PDO";
        case sdo_abort::kPdoLengthExceeded: return "number and length of mapped objects exceed the PDO length";
        case sdo_abort::kParameterIncompatibility: return "general parameter incompatibility";
        case sdo_abort::kInternalIncompatibility: return "general internal incompatibility in the device";
        case sdo_abort::kHardwareError: return "access failed due to a hardware error";
        case sdo_abort::kLengthMismatch: return "data type does not match, length of service parameter does not match";
        case sdo_abort::kLengthTooHigh: return "data type does not match, length of service parameter too high";
        case sdo_abort::kLengthTooLow: return "data type does not match, length of service parameter too low";
        case sdo_abort::kSubindexDoesNotExist: return "subindex does not exist";
        case sdo_abort::kValueOutOfRange: return "value range of parameter exceeded";
        case sdo_abort::kValueTooHigh: return "value of parameter written too high";
        case sdo_abort::kValueTooLow: return "value of parameter written too low";
        case sdo_abort::kMaximumBelowMinimum: return "maximum value is less than minimum value";
        case sdo_abort::kGeneralError: return "general error";
        case sdo_abort::kCannotStore: return "data cannot be transferred or stored to the application";
        case sdo_abort::kCannotStoreLocalControl: return "data cannot be transferred or stored because of local control";
        case sdo_abort::kCannotStoreInState: return "data cannot be transferred or stored because of the present device state";
        case sdo_abort::kNoObjectDictionary: return "object dictionary dynamic generation failed or no object dictionary present";
        case sdo_abort::kNoDataAvailable: return "no data available";
        default: return "unknown SDO abort code";
    }
}

}  // namespace ecpair::wire
