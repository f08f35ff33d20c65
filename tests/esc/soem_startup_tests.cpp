// The acceptance test of the emulation: SOEM's start-up (ethercatconfig.c
// ecx_config_init + ecx_config_map, esc-facts.md §3), replayed datagram by
// datagram against the slaves of every shared ENI, must find every slave,
// read its SII, bring it to PREOP, SAFEOP and OP, and exchange process data
// with the expected working counter. (SOEM's CoE PDO upload is left out:
// it falls back to the SII PDOs when the slave has no CoE server.)

#include <filesystem>

#include <catch2/catch.hpp>

#include "ecpair/eni/loader.hpp"
#include "esc_test_support.hpp"
#include "soem_sii_reader.hpp"

using namespace ecpair;
using namespace ecpair::sim;
using namespace ecpair::sim::test;
using wire::Command;

namespace {

struct SmSetting {
    std::uint16_t start = 0;
    std::uint16_t length = 0;
    std::uint32_t flags = 0;  // control | activate << 16, as SOEM keeps them
    std::uint8_t type = 0;    // 3 outputs, 4 inputs
};

std::vector<std::uint8_t> encode(const SmSetting& sm) {
    auto out = le16(sm.start);
    for (auto b : le16(sm.length)) out.push_back(b);
    for (auto b : le32(sm.flags)) out.push_back(b);
    return out;
}

std::vector<std::uint8_t> fmmu(std::uint32_t logical, std::uint16_t length, std::uint16_t physical, bool outputs) {
    auto out = le32(logical);
    for (auto b : le16(length)) out.push_back(b);
    out.push_back(0);
    out.push_back(7);
    for (auto b : le16(physical)) out.push_back(b);
    out.push_back(0);
    out.push_back(outputs ? 2 : 1);
    out.push_back(1);
    out.insert(out.end(), {0, 0, 0});
    return out;
}

void bwr(Line& line, std::uint16_t ado, const std::vector<std::uint8_t>& data) {
    CHECK(line.transact(physical(Command::Bwr, 0, ado, data)).wkc == line.size());
}

std::uint8_t al_state(Line& line, std::uint16_t station) { return line.fprd(station, 0x0130, 1)[0]; }

}  // namespace

TEST_CASE("SOEM's start-up brings the slaves of every shared ENI to OP") {
    for (const auto& entry : std::filesystem::directory_iterator(ECPAIR_TEST_ENI_DIR)) {
        if (entry.path().extension() != ".xml") continue;
        const auto loaded = eni::load_eni_file(entry.path().string());
        REQUIRE(loaded.has_value());
        const auto& slaves = loaded.value()->slaves;
        if (slaves.empty()) continue;
        INFO(entry.path().filename().string());
        std::vector<EscDescription> descriptions;
        for (const auto& slave : slaves) descriptions.push_back(EscDescription::from_eni(slave));
        Line line(descriptions);
        const std::size_t n = line.size();

        // ecx_detect_slaves
        bwr(line, 0x0103, {0});
        bwr(line, 0x0120, {0x11});
        bwr(line, 0x0120, {0x11});
        REQUIRE(line.transact(physical_read(Command::Brd, 0, 0x0000, 2)).wkc == n);
        // ecx_set_slaves_to_default
        bwr(line, 0x0101, {0});
        bwr(line, 0x0200, le16(0x0004));
        bwr(line, 0x0300, std::vector<std::uint8_t>(8, 0));
        bwr(line, 0x0600, std::vector<std::uint8_t>(48, 0));
        bwr(line, 0x0800, std::vector<std::uint8_t>(32, 0));
        bwr(line, 0x0981, {0});
        bwr(line, 0x0910, std::vector<std::uint8_t>(4, 0));
        bwr(line, 0x0930, le16(0x1000));
        bwr(line, 0x0934, le16(0x0C00));
        bwr(line, 0x0103, {0});
        bwr(line, 0x0120, {0x11});
        bwr(line, 0x0500, {0x02});
        bwr(line, 0x0500, {0x00});

        std::vector<std::array<SmSetting, 8>> sm_settings(n);
        std::vector<std::uint16_t> mailbox_length(n, 0);
        for (std::size_t i = 0; i < n; ++i) {
            INFO("slave " << i + 1);
            const auto adp = static_cast<std::uint16_t>(0x10000 - i);
            const auto station = static_cast<std::uint16_t>(kFirstStation + i);
            CHECK(line.transact(physical_read(Command::Aprd, adp, 0x0140, 2)).wkc == 1);
            CHECK(line.transact(physical(Command::Apwr, adp, 0x0010, le16(station))).wkc == 1);
            CHECK(line.transact(physical(Command::Apwr, adp, 0x0100, le16(i == 0 ? 1 : 0))).wkc == 1);
            CHECK(line.transact(physical_read(Command::Aprd, adp, 0x0010, 2)).data == le16(station));
            CHECK(line.transact(physical_read(Command::Fprd, station, 0x0012, 2)).wkc == 1);
            CHECK((line.fprd(station, 0x0502, 2)[0] & 0x40) != 0);  // reads 8 bytes at a time

            SoemSiiReader sii(line, station);
            CHECK(sii.dword(0x08) == slaves[i].info.vendor_id);
            CHECK(sii.dword(0x0A) == slaves[i].info.product_code);
            CHECK(sii.dword(0x0C) == slaves[i].info.revision_no);
            mailbox_length[i] = sii.word(0x19);
            CHECK((line.fprd(station, 0x0008, 2)[0] & 0x04) != 0);  // DC
            const auto topology = line.fprd(station, 0x0110, 2);
            CHECK((topology[1] & 0x03) == 0x02);  // port 0 open, communication established
            CHECK(line.fprd(station, 0x0007, 1)[0] != 0);

            auto& sms = sm_settings[i];
            if (mailbox_length[i] > 0) {
                sms[0] = SmSetting{sii.word(0x18), mailbox_length[i], 0x00010026, 0};
                sms[1] = SmSetting{sii.word(0x1A), sii.word(0x1B), 0x00010022, 0};
            }
            const auto sii_sms = sii.sync_managers();
            for (std::size_t s = 0; s < sii_sms.size() && s < sms.size(); ++s) {
                sms[s].start = sii_sms[s].start;
                sms[s].length = sii_sms[s].length;
                sms[s].flags = sii_sms[s].control | (std::uint32_t{sii_sms[s].enable} << 16);
            }
            if (mailbox_length[i] > 0) {
                auto both = encode(sms[0]);
                for (auto b : encode(sms[1])) both.push_back(b);
                CHECK(line.fpwr(station, 0x0800, both) == 1);
            }
            // SM lengths from the SII PDOs (ecx_map_sii), read before the
            // EEPROM goes to the PDI.
            const auto in_bits = sii.pdo_bits(true);
            const auto out_bits = sii.pdo_bits(false);
            for (std::size_t s = 0; s < sms.size(); ++s) {
                if (in_bits[s] > 0) sms[s] = SmSetting{sms[s].start, static_cast<std::uint16_t>((in_bits[s] + 7) / 8), sms[s].flags, 4};
                if (out_bits[s] > 0) sms[s] = SmSetting{sms[s].start, static_cast<std::uint16_t>((out_bits[s] + 7) / 8), sms[s].flags, 3};
            }
            CHECK(line.fpwr(station, 0x0500, {0x01}) == 1);  // ecx_eeprom2pdi
            CHECK(line.fpwr(station, 0x0120, le16(0x0012)) == 1);
            CHECK(al_state(line, station) == 0x02);
        }

        // ecx_config_map: SyncManagers and FMMUs (outputs first, then inputs), then SAFEOP.
        std::uint32_t outputs = 0;
        std::uint32_t inputs = 0;
        for (const auto& sms : sm_settings) {
            for (const auto& sm : sms) {
                if (sm.type == 3) outputs += sm.length;
                if (sm.type == 4) inputs += sm.length;
            }
        }
        std::uint32_t out_cursor = 0;
        std::uint32_t in_cursor = outputs;
        std::uint16_t expected_wkc = 0;
        for (std::size_t i = 0; i < n; ++i) {
            INFO("slave " << i + 1);
            const auto station = static_cast<std::uint16_t>(kFirstStation + i);
            auto& sms = sm_settings[i];
            for (std::size_t s = 0; s < sms.size(); ++s) {
                SmSetting& sm = sms[s];
                if (sm.start == 0 || (s < 2 && mailbox_length[i] > 0)) continue;
                sm.flags = sm.length == 0 ? (sm.flags & 0xFFFEFFFF) : (sm.flags | 0x00010000);
                CHECK(line.fpwr(station, static_cast<std::uint16_t>(0x0800 + 8 * s), encode(sm)) == 1);
            }
            std::uint16_t next_fmmu = 0x0600;
            bool has_outputs = false;
            bool has_inputs = false;
            for (const auto& sm : sms) {
                if (sm.length == 0 || (sm.type != 3 && sm.type != 4)) continue;
                const bool out = sm.type == 3;
                std::uint32_t& cursor = out ? out_cursor : in_cursor;
                CHECK(line.fpwr(station, next_fmmu, fmmu(cursor, sm.length, sm.start, out)) == 1);
                next_fmmu = static_cast<std::uint16_t>(next_fmmu + 16);
                cursor += sm.length;
                (out ? has_outputs : has_inputs) = true;
            }
            expected_wkc = static_cast<std::uint16_t>(expected_wkc + (has_outputs ? 2 : 0) + (has_inputs ? 1 : 0));
            CHECK(line.fpwr(station, 0x0120, le16(0x0004)) == 1);
            CHECK(al_state(line, station) == 0x04);
        }
        bwr(line, 0x0120, le16(0x0008));
        for (std::size_t i = 0; i < n; ++i) CHECK(al_state(line, static_cast<std::uint16_t>(kFirstStation + i)) == 0x08);

        if (outputs + inputs > 0) {
            const Datagram lrw = line.transact(logical(Command::Lrw, 0, std::vector<std::uint8_t>(outputs + inputs, 0x5A)));
            CHECK(lrw.wkc == expected_wkc);
        }
    }
}
