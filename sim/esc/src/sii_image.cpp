// The image is written front to back by a small little-endian writer: the
// fixed 64-word header, then one category after the other (type word, length
// word, data padded to whole words), then the end marker. Category layouts
// follow ETG.1000.6 tables 20-24 and are what SOEM (ecx_siiSM, ecx_siiPDO,
// ecx_siistring) and ethercrab (eeprom/types.rs) parse.

#include "sii_image.hpp"

#include <algorithm>
#include <array>
#include <string>
#include <string_view>

#include <fmt/format.h>

#include "coe_data_types.hpp"
#include "ecpair/wire/esc_registers.hpp"

namespace ecpair::sim {
namespace {

namespace cat = wire::reg::sii;

constexpr std::size_t kHeaderBytes = 0x40 * 2;

class ImageWriter {
public:
    void u8(std::uint8_t value) { bytes_.push_back(value); }
    void u16(std::uint16_t value) {
        u8(static_cast<std::uint8_t>(value));
        u8(static_cast<std::uint8_t>(value >> 8));
    }
    void u32(std::uint32_t value) {
        u16(static_cast<std::uint16_t>(value));
        u16(static_cast<std::uint16_t>(value >> 16));
    }
    void word_at(std::uint16_t word, std::uint16_t value) { store_le<std::uint16_t>(bytes_, word * 2U, value); }
    void dword_at(std::uint16_t word, std::uint32_t value) { store_le<std::uint32_t>(bytes_, word * 2U, value); }
    void zeros(std::size_t count) { bytes_.insert(bytes_.end(), count, std::uint8_t{0}); }

    void begin_category(std::uint16_t type) {
        u16(type);
        length_at_ = bytes_.size();
        u16(0);
    }
    void end_category() {
        if (bytes_.size() % 2 != 0) u8(0);
        const std::size_t data_bytes = bytes_.size() - length_at_ - 2;
        store_le<std::uint16_t>(bytes_, length_at_, static_cast<std::uint16_t>(data_bytes / 2));
    }

    std::vector<std::uint8_t>& bytes() { return bytes_; }

private:
    std::vector<std::uint8_t> bytes_;
    std::size_t length_at_ = 0;
};

std::string clipped(const std::string& text) { return text.substr(0, 255); }

// SII word 0: PDI control (0x0140) and ESC configuration (0x0141).
std::uint16_t pdi_control_word(const EscLayout& layout) {
    return layout.device_emulation ? sii::kDigitalIoDeviceEmulation : sii::kPdiControlWord;
}

void write_strings(ImageWriter& w, const std::array<std::string, 3>& strings) {
    w.begin_category(cat::kCategoryStrings);
    w.u8(static_cast<std::uint8_t>(strings.size()));
    for (const auto& s : strings) {
        w.u8(static_cast<std::uint8_t>(s.size()));
        for (const char c : s) w.u8(static_cast<std::uint8_t>(c));
    }
    w.end_category();
}

void write_general(ImageWriter& w, const EscLayout& layout) {
    w.begin_category(cat::kCategoryGeneral);
    w.u8(2);  // group string
    w.u8(0);  // image string
    w.u8(3);  // order string
    w.u8(1);  // name string
    w.u8(0);
    // CoE details: b0 SDO, b1 SDO Information, b2 PDO assignment, b3 PDO
    // configuration, b5 SDO CompleteAccess (b4 upload at start-up: no).
    w.u8((layout.mailbox_protocols & eni::kCoE) != 0 ? 0x2F : 0x00);
    w.u8((layout.mailbox_protocols & eni::kFoE) != 0 ? 0x01 : 0x00);  // FoE details
    w.u8((layout.mailbox_protocols & eni::kEoE) != 0 ? 0x01 : 0x00);  // EoE details
    w.u8(0);                                                          // SoE channels
    w.u8(0);                                                          // DS402 channels
    w.u8(0);                                                          // SysmanClass
    // Flags: b2 mailbox data link layer, b3 explicit device ID in AL status
    // code (which needs a stack: not in device emulation).
    w.u8(static_cast<std::uint8_t>((layout.mailbox_data_link_layer ? 0x04 : 0x00) | (layout.device_emulation ? 0x00 : 0x08)));
    w.u16(0);  // EBUS current
    std::uint16_t ports = 0;
    for (int p = 0; p < 4; ++p) {
        const char physics = layout.port_physics[static_cast<std::size_t>(p)];
        const std::uint16_t code = physics == 'Y' ? 0x1 : physics == 'K' ? 0x3 : 0x0;  // MII / EBUS / unused
        ports = static_cast<std::uint16_t>(ports | (code << (4 * p)));
    }
    w.u16(ports);
    w.u16(0);  // physical memory address of an identification (not used)
    w.zeros(12);
    w.end_category();
}

void write_fmmu_usage(ImageWriter& w, const EscLayout& layout) {
    const auto has = [&](SmRole role) {
        return std::any_of(layout.sms.begin(), layout.sms.end(), [&](const SmPlan& p) { return p.role == role; });
    };
    std::vector<std::uint8_t> usage;
    if (has(SmRole::Outputs)) usage.push_back(0x01);
    if (has(SmRole::Inputs)) usage.push_back(0x02);
    if (layout.has_mailbox()) usage.push_back(0x03);  // mailbox state
    if (usage.empty()) return;
    if (usage.size() % 2 != 0) usage.push_back(0xFF);
    w.begin_category(cat::kCategoryFmmu);
    for (const auto u : usage) w.u8(u);
    w.end_category();
}

void write_sync_managers(ImageWriter& w, const EscLayout& layout) {
    if (layout.described_sm_count == 0) return;
    w.begin_category(cat::kCategorySyncManager);
    for (int n = 0; n < layout.described_sm_count; ++n) {
        const SmPlan& plan = layout.sms[static_cast<std::size_t>(n)];
        w.u16(plan.start);
        w.u16(plan.length);
        w.u8(plan.control);
        w.u8(0);  // status
        w.u8(plan.enable ? 0x01 : 0x00);
        w.u8(static_cast<std::uint8_t>(plan.role));
    }
    w.end_category();
}

void write_pdos(ImageWriter& w, const EscLayout& layout, bool inputs) {
    const auto in_category = [&](const AssignedPdo& a) { return a.inputs == inputs; };
    if (std::none_of(layout.pdos.begin(), layout.pdos.end(), in_category)) return;
    w.begin_category(inputs ? cat::kCategoryTxPdo : cat::kCategoryRxPdo);
    for (const AssignedPdo& assigned : layout.pdos) {
        if (!in_category(assigned)) continue;
        const eni::Pdo& pdo = *assigned.pdo;
        // An entry longer than 255 bits does not fit the SII's bit length
        // byte: it is split so that the PDO keeps its size.
        std::size_t entry_count = 0;
        for (const auto& entry : pdo.entries) entry_count += std::max<std::size_t>(1, (entry.bit_length + 254U) / 255U);
        w.u16(pdo.index);
        w.u8(static_cast<std::uint8_t>(std::min<std::size_t>(entry_count, 255)));
        w.u8(assigned.sm);
        w.u8(0);  // DC sync
        w.u8(0);  // name string
        const std::uint16_t flags =
            static_cast<std::uint16_t>((pdo.mandatory ? 0x0001 : 0x0000) | 0x0002 | (pdo.fixed ? 0x0010 : 0x0000));
        w.u16(flags);
        std::size_t written = 0;
        for (const auto& entry : pdo.entries) {
            std::uint32_t remaining = entry.bit_length;
            do {
                if (written == 255) break;
                const auto bits = static_cast<std::uint8_t>(std::min<std::uint32_t>(remaining, 255));
                w.u16(entry.index);
                w.u8(entry.subindex);
                w.u8(0);  // name string
                w.u8(static_cast<std::uint8_t>(coe_data_type(entry.data_type)));
                w.u8(bits);
                w.u16(0);
                remaining -= bits;
                ++written;
            } while (remaining > 0);
        }
    }
    w.end_category();
}

}  // namespace

std::uint8_t sii_crc8(ConstBytes bytes) {
    std::uint8_t crc = 0xFF;
    for (const std::uint8_t byte : bytes) {
        crc = static_cast<std::uint8_t>(crc ^ byte);
        for (int i = 0; i < 8; ++i) {
            crc = static_cast<std::uint8_t>((crc & 0x80) != 0 ? (crc << 1) ^ 0x07 : crc << 1);
        }
    }
    return crc;
}

bool sii_checksum_valid(ConstBytes image) {
    if (image.size() < 16) return false;
    return load_le<std::uint16_t>(image, sii::kConfigWords * 2U) == sii_crc8(image.first(sii::kConfigWords * 2U));
}

void sii_set_alias(Bytes image, std::uint16_t alias) {
    store_le<std::uint16_t>(image, cat::kAlias * 2U, alias);
    store_le<std::uint16_t>(image, cat::kChecksum * 2U, sii_crc8(ConstBytes(image).first(sii::kConfigWords * 2U)));
}

std::vector<std::uint8_t> build_sii_image(const EscDescription& description, const EscLayout& layout) {
    ImageWriter w;
    w.zeros(kHeaderBytes);
    w.word_at(0x0000, pdi_control_word(layout));
    w.word_at(0x0002, sii::kSyncPulseLength);
    w.dword_at(cat::kVendorId, description.vendor_id);
    w.dword_at(cat::kProductCode, description.product_code);
    w.dword_at(cat::kRevision, description.revision_no);
    w.dword_at(cat::kSerial, description.serial_no);
    if (layout.bootstrap) {
        w.word_at(cat::kBootstrapRxMailbox, layout.bootstrap->out.start);
        w.word_at(cat::kBootstrapRxMailbox + 1, layout.bootstrap->out.length);
        w.word_at(cat::kBootstrapRxMailbox + 2, layout.bootstrap->in.start);
        w.word_at(cat::kBootstrapRxMailbox + 3, layout.bootstrap->in.length);
    }
    if (layout.mailbox) {
        w.word_at(cat::kStandardRxMailbox, layout.mailbox->out.start);
        w.word_at(cat::kStandardRxMailbox + 1, layout.mailbox->out.length);
        w.word_at(cat::kStandardRxMailbox + 2, layout.mailbox->in.start);
        w.word_at(cat::kStandardRxMailbox + 3, layout.mailbox->in.length);
        w.word_at(cat::kMailboxProtocols, layout.mailbox_protocols);
    }
    w.word_at(cat::kVersion, 1);

    write_strings(w, {clipped(description.name), std::string("ecsim"),
                      fmt::format("{:08X}:{:08X}", description.vendor_id, description.product_code)});
    write_general(w, layout);
    write_fmmu_usage(w, layout);
    write_sync_managers(w, layout);
    write_pdos(w, layout, true);
    write_pdos(w, layout, false);
    w.u16(cat::kCategoryEnd);

    std::vector<std::uint8_t>& image = w.bytes();
    std::size_t kibit = 2;  // the smallest SII EEPROM
    while (kibit * 128 < image.size()) kibit *= 2;
    w.word_at(cat::kSize, static_cast<std::uint16_t>(kibit - 1));
    sii_set_alias(image, description.alias);
    image.resize(kibit * 128, 0xFF);
    return std::move(image);
}

}  // namespace ecpair::sim
