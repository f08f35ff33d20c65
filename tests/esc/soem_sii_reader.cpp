#include "soem_sii_reader.hpp"

#include <stdexcept>

namespace ecpair::sim::test {
namespace {

constexpr std::uint16_t kControl = 0x0502;
constexpr std::uint16_t kData = 0x0508;
constexpr std::uint16_t kBusy = 0x8000;
constexpr std::uint16_t kReadEightBytes = 0x0040;
constexpr std::uint16_t kErrors = 0x7800;
constexpr std::uint16_t kCategoryStrings = 10;
constexpr std::uint16_t kCategorySm = 41;
constexpr std::uint16_t kCategoryTxPdo = 50;

std::uint16_t to_u16(const std::vector<std::uint8_t>& raw) {
    return static_cast<std::uint16_t>(raw.at(0) | (raw.at(1) << 8));
}

}  // namespace

void SoemSiiReader::read_chunk(std::uint32_t word_address) {
    auto status = to_u16(line_.fprd(station_, kControl, 2));
    if ((status & kErrors) != 0) line_.fpwr(station_, kControl, le16(0x0000));  // EC_ECMD_NOP clears errors
    const std::vector<std::uint8_t> command = {0x00, 0x01, static_cast<std::uint8_t>(word_address),
                                               static_cast<std::uint8_t>(word_address >> 8), 0x00, 0x00};
    if (line_.fpwr(station_, kControl, command) != 1) throw std::runtime_error("EEPROM command not accepted");
    ++read_commands_;
    int polls = 0;
    do {
        status = to_u16(line_.fprd(station_, kControl, 2));
        if (++polls > 10) throw std::runtime_error("EEPROM stays busy");
    } while ((status & kBusy) != 0);
    if ((status & kErrors) != 0) throw std::runtime_error("EEPROM read failed");
    eight_bytes_ = (status & kReadEightBytes) != 0;
    const std::uint32_t count = eight_bytes_ ? 8 : 4;
    const auto data = line_.fprd(station_, kData, count);
    for (std::uint32_t i = 0; i < count; ++i) cache_[word_address * 2 + i] = data[i];
}

std::uint8_t SoemSiiReader::byte(std::uint32_t address) {
    if (auto it = cache_.find(address); it != cache_.end()) return it->second;
    read_chunk(address / 2);
    return cache_.at(address);
}

std::uint16_t SoemSiiReader::word(std::uint32_t word_address) {
    return static_cast<std::uint16_t>(byte(word_address * 2) | (byte(word_address * 2 + 1) << 8));
}

std::uint32_t SoemSiiReader::dword(std::uint32_t word_address) {
    return static_cast<std::uint32_t>(word(word_address)) | (static_cast<std::uint32_t>(word(word_address + 1)) << 16);
}

std::uint32_t SoemSiiReader::find(std::uint16_t category) {
    std::uint32_t a = 0x40 * 2;
    std::uint16_t p = static_cast<std::uint16_t>(byte(a) | (byte(a + 1) << 8));
    a += 2;
    while (p != category && p != 0xFFFF) {
        const auto length = static_cast<std::uint16_t>(byte(a) | (byte(a + 1) << 8));
        a += 2 + 2U * length;
        p = static_cast<std::uint16_t>(byte(a) | (byte(a + 1) << 8));
        a += 2;
        if (a > 0x20000) return 0;
    }
    return p == category ? a : 0;
}

std::string SoemSiiReader::string(std::uint8_t index) {
    const std::uint32_t a = find(kCategoryStrings);
    if (a == 0) return {};
    std::uint32_t b = a + 2;
    const std::uint8_t count = byte(b++);
    if (index == 0 || index > count) return {};
    for (std::uint8_t i = 1; i < index; ++i) b += 1U + byte(b);
    const std::uint8_t length = byte(b++);
    std::string text;
    for (std::uint8_t i = 0; i < length; ++i) text.push_back(static_cast<char>(byte(b + i)));
    return text;
}

std::vector<SoemSiiReader::SyncManager> SoemSiiReader::sync_managers() {
    std::vector<SyncManager> sms;
    const std::uint32_t a = find(kCategorySm);
    if (a == 0) return sms;
    const auto words = static_cast<std::uint16_t>(byte(a) | (byte(a + 1) << 8));
    for (std::uint32_t n = 0; n < words / 4U; ++n) {
        const std::uint32_t at = a + 2 + 8 * n;
        SyncManager sm;
        sm.start = static_cast<std::uint16_t>(byte(at) | (byte(at + 1) << 8));
        sm.length = static_cast<std::uint16_t>(byte(at + 2) | (byte(at + 3) << 8));
        sm.control = byte(at + 4);
        sm.enable = byte(at + 6);
        sm.type = byte(at + 7);
        sms.push_back(sm);
    }
    return sms;
}

std::array<std::uint32_t, 8> SoemSiiReader::pdo_bits(bool tx) {
    std::array<std::uint32_t, 8> bits{};
    const std::uint32_t start = find(static_cast<std::uint16_t>(kCategoryTxPdo + (tx ? 0 : 1)));
    if (start == 0) return bits;
    std::uint32_t a = start;
    const auto length = static_cast<std::uint16_t>(byte(a) | (byte(a + 1) << 8));
    a += 2;
    std::uint32_t c = 1;  // words consumed, as SOEM counts them
    do {
        a += 2;  // PDO index
        ++c;
        const std::uint8_t entries = byte(a++);
        const std::uint8_t sm = byte(a++);
        a += 4;
        c += 2;
        std::uint32_t pdo = 0;
        for (std::uint8_t e = 0; e < entries; ++e) {
            c += 4;
            a += 5;
            pdo += byte(a++);
            a += 2;
        }
        ++c;
        if (sm < bits.size()) bits[sm] += pdo;
    } while (c < length);
    return bits;
}

std::uint8_t igh_sii_crc(const std::vector<std::uint8_t>& data) {
    std::uint8_t crc = 0x48;
    for (const std::uint8_t byte : data) {
        for (int i = 0; i < 8; ++i) {
            const bool top = (crc & 0x80) != 0;
            crc = static_cast<std::uint8_t>((crc << 1) | ((byte >> (7 - i)) & 0x01));
            if (top) crc = static_cast<std::uint8_t>(crc ^ 0x07);
        }
    }
    for (int i = 0; i < 8; ++i) {
        const bool top = (crc & 0x80) != 0;
        crc = static_cast<std::uint8_t>(crc << 1);
        if (top) crc = static_cast<std::uint8_t>(crc ^ 0x07);
    }
    return crc;
}

}  // namespace ecpair::sim::test
