// The interface is driven from the end of the frame: filter_staged() before
// the commit, on_ecat_write() after it. Status bits other than the command
// live in 0x0502 itself, so what the master polls is what the unit decided.

#include "sii_eeprom.hpp"

#include <algorithm>

#include "ecpair/wire/esc_registers.hpp"
#include "register_map.hpp"
#include "sii_image.hpp"

namespace ecpair::sim {
namespace {

namespace reg = wire::reg;

constexpr std::uint16_t kWriteEnable = 0x0001;
constexpr std::uint16_t kReadEightBytes = 0x0040;
constexpr std::uint16_t kTwoAddressBytes = 0x0080;
constexpr std::uint16_t kCommandMask = 0x0700;
constexpr std::uint16_t kChecksumError = 0x0800;
constexpr std::uint16_t kNotLoaded = 0x1000;
constexpr std::uint16_t kCommandError = 0x2000;
constexpr std::uint16_t kWriteEnableError = 0x4000;

constexpr unsigned kCommandRead = 1;
constexpr unsigned kCommandWrite = 2;
constexpr unsigned kCommandReload = 4;

constexpr std::uint8_t kPdiAccess = 0x01;
constexpr std::uint8_t kForceEcatAccess = 0x02;

constexpr std::size_t kChunkBytes = 8;

void update_status(EscMemory& memory, std::uint16_t set, std::uint16_t clear) {
    const auto status = memory.load<std::uint16_t>(reg::kSiiControl);
    memory.store<std::uint16_t>(reg::kSiiControl, static_cast<std::uint16_t>((status & ~clear) | set));
}

}  // namespace

SiiEeprom::SiiEeprom(std::vector<std::uint8_t> image) : image_(std::move(image)) {}

void SiiEeprom::set_alias(std::uint16_t alias) { sii_set_alias(image_, alias); }

bool SiiEeprom::power_on(EscMemory& memory) {
    memory.set_u8(reg::kSiiConfig, 0);
    memory.set_u8(reg::kSiiPdiAccess, 0);
    memory.store<std::uint16_t>(reg::kSiiControl, kReadEightBytes | kTwoAddressBytes);
    loaded_ = load_configuration(memory, true);
    return loaded_;
}

std::uint16_t SiiEeprom::alias() const { return load_le<std::uint16_t>(image_, reg::sii::kAlias * 2U); }

bool SiiEeprom::load_configuration(EscMemory& memory, bool first_load) {
    if (!sii_checksum_valid(image_)) {
        update_status(memory, kChecksumError | kNotLoaded, 0);
        return false;
    }
    const auto word = [&](std::uint16_t w) { return load_le<std::uint16_t>(image_, w * 2U); };
    memory.store<std::uint16_t>(reg::kPdiControl, word(0));
    memory.store<std::uint16_t>(regs::kPdiConfig, word(1));
    memory.store<std::uint16_t>(regs::kDcSyncPulseLength, word(2));
    memory.store<std::uint16_t>(regs::kPdiConfigExtended, word(3));
    if (first_load) memory.store<std::uint16_t>(reg::kStationAlias, word(reg::sii::kAlias));
    memory.store<std::uint16_t>(regs::kEscConfigA5, word(5));
    memory.store<std::uint16_t>(regs::kEscConfigA6, word(6));
    update_status(memory, 0, kChecksumError | kNotLoaded);
    return true;
}

void SiiEeprom::filter_staged(EscMemory& memory) const {
    const bool pdi_controls = ((memory.u8(reg::kSiiConfig) | memory.u8(reg::kSiiPdiAccess)) & kPdiAccess) != 0;
    if (pdi_controls) memory.discard_staged(reg::kSiiControl, reg::kSiiData + kChunkBytes);
}

bool SiiEeprom::on_ecat_write(EscMemory& memory) {
    if (memory.staged_any(reg::kSiiConfig, reg::kSiiConfig + 1) && (memory.u8(reg::kSiiConfig) & kForceEcatAccess) != 0) {
        memory.set_u8(reg::kSiiPdiAccess, 0);  // the PDI loses the EEPROM
    }
    if (!memory.staged_any(reg::kSiiControl, reg::kSiiControl + 2)) return loaded_;

    auto status = memory.load<std::uint16_t>(reg::kSiiControl);
    const unsigned command = (status & kCommandMask) >> 8;
    const bool write_enabled = (status & kWriteEnable) != 0;
    status = static_cast<std::uint16_t>(status & ~(kCommandMask | kWriteEnable));  // self-clearing
    const std::uint32_t word_address = memory.load<std::uint32_t>(reg::kSiiAddress);
    switch (command) {
        case 0: status = static_cast<std::uint16_t>(status & ~(kCommandError | kWriteEnableError)); break;
        case kCommandRead: read_chunk(memory, word_address, status); break;
        case kCommandWrite:
            if (write_enabled) {
                write_word(memory, word_address, status);
            } else {
                status = static_cast<std::uint16_t>(status | kWriteEnableError);
            }
            break;
        case kCommandReload: break;
        default: status = static_cast<std::uint16_t>(status | kCommandError); break;
    }
    memory.store<std::uint16_t>(reg::kSiiControl, status);
    if (command == kCommandReload) loaded_ = load_configuration(memory, false);
    return loaded_;
}

void SiiEeprom::read_chunk(EscMemory& memory, std::uint32_t word_address, std::uint16_t& status) const {
    const std::uint64_t first = std::uint64_t{word_address} * 2;
    if (first >= image_.size()) {
        status = static_cast<std::uint16_t>(status | kCommandError);
        return;
    }
    for (std::size_t i = 0; i < kChunkBytes; ++i) {
        const std::uint64_t at = first + i;
        memory.set_u8(static_cast<std::uint16_t>(reg::kSiiData + i),
                      at < image_.size() ? image_[static_cast<std::size_t>(at)] : std::uint8_t{0xFF});
    }
}

void SiiEeprom::write_word(EscMemory& memory, std::uint32_t word_address, std::uint16_t& status) {
    const std::uint64_t first = std::uint64_t{word_address} * 2;
    if (first + 2 > image_.size()) {
        status = static_cast<std::uint16_t>(status | kCommandError);
        return;
    }
    image_[static_cast<std::size_t>(first)] = memory.u8(reg::kSiiData);
    image_[static_cast<std::size_t>(first) + 1] = memory.u8(reg::kSiiData + 1);
}

}  // namespace ecpair::sim
