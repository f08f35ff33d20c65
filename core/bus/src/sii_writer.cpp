#include "ecpair/bus/sii_writer.hpp"

#include <fmt/format.h>

#include "ecpair/common/bytes.hpp"
#include "ecpair/wire/esc_registers.hpp"
#include "sii_interface.hpp"

namespace ecpair::bus {

namespace sii = sii_interface;

namespace {

constexpr std::uint16_t kAliasWord = wire::reg::sii::kAlias;
constexpr std::uint16_t kChecksumWord = wire::reg::sii::kChecksum;

}  // namespace

std::uint8_t sii_configuration_crc(const std::vector<std::uint16_t>& words) {
    std::uint8_t crc = 0xFF;
    for (std::size_t w = 0; w < 7 && w < words.size(); ++w) {
        for (const auto byte : {static_cast<std::uint8_t>(words[w] & 0xFF), static_cast<std::uint8_t>(words[w] >> 8)}) {
            crc = static_cast<std::uint8_t>(crc ^ byte);
            for (int i = 0; i < 8; ++i) crc = static_cast<std::uint8_t>((crc & 0x80) != 0 ? (crc << 1) ^ 0x07 : crc << 1);
        }
    }
    return crc;
}

Expected<void, BusError> SiiWriter::write_word(SlaveAddress slave, std::uint16_t word_address, std::uint16_t value) {
    auto idle = sii::wait_idle(bus_, slave, busy_polls_);
    if (!idle) return unexpected(idle.error());
    if (auto cleared = sii::clear_errors(bus_, slave, *idle); !cleared) return unexpected(cleared.error());
    std::vector<std::uint8_t> data(2);
    store_le<std::uint16_t>(data, 0, value);
    if (auto put = write_register(bus_, slave, wire::reg::kSiiData, data); !put || put->wkc == 0) {
        return unexpected(put ? sii::error(slave, "data register not writable") : put.error());
    }
    std::vector<std::uint8_t> command = {sii::kWriteEnable, sii::kWriteCommand, 0, 0, 0, 0};
    store_le<std::uint16_t>(command, 2, word_address);
    auto issued = write_register(bus_, slave, wire::reg::kSiiControl, command);
    if (!issued) return unexpected(issued.error());
    if (issued->wkc == 0) return unexpected(sii::error(slave, "write command not accepted"));
    auto done = sii::wait_idle(bus_, slave, busy_polls_);
    if (!done) return unexpected(done.error());
    if ((*done & sii::kWriteEnableError) != 0) return unexpected(sii::error(slave, "write enable refused"));
    if ((*done & sii::kCommandError) != 0) {
        return unexpected(sii::error(slave, fmt::format("write of word 0x{:04x} not acknowledged", word_address)));
    }
    return {};
}

Expected<std::uint16_t, BusError> SiiWriter::set_station_alias(SlaveAddress slave, std::uint16_t alias) {
    SiiReader reader(bus_, busy_polls_);
    auto words = reader.read_words(slave, 0, kChecksumWord);
    if (!words) return unexpected(words.error());
    const std::uint16_t before = (*words)[kAliasWord];
    (*words)[kAliasWord] = alias;
    if (auto w = write_word(slave, kAliasWord, alias); !w) return unexpected(w.error());
    if (auto w = write_word(slave, kChecksumWord, sii_configuration_crc(*words)); !w) return unexpected(w.error());
    return before;
}

}  // namespace ecpair::bus
