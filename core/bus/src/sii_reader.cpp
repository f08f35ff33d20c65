#include "ecpair/bus/sii_reader.hpp"

#include <fmt/format.h>

#include "ecpair/common/bytes.hpp"
#include "ecpair/wire/esc_registers.hpp"
#include "sii_interface.hpp"

namespace ecpair::bus {

namespace sii = sii_interface;

Expected<std::vector<std::uint8_t>, BusError> SiiReader::read_chunk(SlaveAddress slave,
                                                                    std::uint16_t word_address) {
    auto idle = sii::wait_idle(bus_, slave, busy_polls_);
    if (!idle) return unexpected(idle.error());
    if (auto cleared = sii::clear_errors(bus_, slave, *idle); !cleared) return unexpected(cleared.error());
    // Control word (read command in bits 10:8) and the 32-bit word address in one write.
    std::vector<std::uint8_t> command = {0x00, sii::kReadCommand, 0, 0, 0, 0};
    store_le<std::uint16_t>(command, 2, word_address);
    auto issued = write_register(bus_, slave, wire::reg::kSiiControl, command);
    if (!issued) return unexpected(issued.error());
    if (issued->wkc == 0) return unexpected(sii::error(slave, "read command not accepted"));

    auto done = sii::wait_idle(bus_, slave, busy_polls_);
    if (!done) return unexpected(done.error());
    if ((*done & sii::kCommandError) != 0) {
        return unexpected(sii::error(slave, fmt::format("read of word 0x{:04x} not acknowledged", word_address)));
    }
    const std::size_t length = (*done & sii::kEightByteRead) != 0 ? 8 : 4;
    auto data = read_register(bus_, slave, wire::reg::kSiiData, length);
    if (!data) return unexpected(data.error());
    if (data->wkc == 0) return unexpected(sii::error(slave, "data register not readable"));
    return std::move(data->data);
}

Expected<std::vector<std::uint16_t>, BusError> SiiReader::read_words(SlaveAddress slave,
                                                                      std::uint16_t word_address,
                                                                      std::size_t word_count) {
    // Hand the EEPROM to ECAT: force (b1) and then release the PDI offer, as masters do.
    for (const std::uint8_t value : {std::uint8_t{0x02}, std::uint8_t{0x00}}) {
        auto taken = write_register(bus_, slave, wire::reg::kSiiConfig, {value});
        if (!taken) return unexpected(taken.error());
    }
    std::vector<std::uint16_t> words;
    words.reserve(word_count);
    while (words.size() < word_count) {
        const auto address = static_cast<std::uint16_t>(word_address + words.size());
        auto chunk = read_chunk(slave, address);
        if (!chunk) return unexpected(chunk.error());
        for (std::size_t i = 0; i + 1 < chunk->size() && words.size() < word_count; i += 2) {
            words.push_back(load_le<std::uint16_t>(*chunk, i));
        }
    }
    return words;
}

Expected<std::uint32_t, BusError> SiiReader::read_dword(SlaveAddress slave, std::uint16_t word_address) {
    auto words = read_words(slave, word_address, 2);
    if (!words) return unexpected(words.error());
    return static_cast<std::uint32_t>((*words)[0]) | (static_cast<std::uint32_t>((*words)[1]) << 16);
}

}  // namespace ecpair::bus
