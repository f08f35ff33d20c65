#include "ecpair/sim/eni_generator.hpp"

#include <algorithm>
#include <optional>
#include <vector>

#include <fmt/format.h>
#include <tinyxml2.h>

namespace ecpair::sim {
namespace {

constexpr std::uint32_t kMaxDatagramData = 1486;
constexpr std::uint16_t kOutputSmStart = 0x1100;
constexpr std::uint16_t kInputSmStart = 0x1400;

std::string hex_le(std::uint64_t value, std::size_t bytes) {
    std::string out;
    for (std::size_t i = 0; i < bytes; ++i) out += fmt::format("{:02x}", (value >> (8 * i)) & 0xff);
    return out;
}

// Writes the XML with one element per call; tinyxml2's printer keeps it readable.
class Writer {
public:
    void open(const char* name) { printer_.OpenElement(name); }
    void close() { printer_.CloseElement(); }
    void attribute(const char* name, const std::string& value) { printer_.PushAttribute(name, value.c_str()); }
    template <class T>
    void leaf(const char* name, const T& value) {
        printer_.OpenElement(name);
        printer_.PushText(fmt::format("{}", value).c_str());
        printer_.CloseElement();
    }
    std::string text() const { return printer_.CStr(); }
    tinyxml2::XMLPrinter& printer() { return printer_; }

private:
    tinyxml2::XMLPrinter printer_;
};

struct Cmd {
    std::vector<std::string> transitions;
    std::string comment;
    int command;
    std::uint16_t adp;
    std::uint16_t ado;
    std::string data;
    std::optional<int> cnt;
    std::optional<std::string> validate;  // data; mask 0x0f per byte
    bool before_slave = false;
};

void write_cmd(Writer& w, const Cmd& c) {
    w.open("InitCmd");
    for (const auto& t : c.transitions) w.leaf("Transition", t);
    if (c.before_slave) w.leaf("BeforeSlave", 1);
    w.leaf("Comment", c.comment);
    w.leaf("Requires", "cycle");
    w.leaf("Cmd", c.command);
    w.leaf("Adp", c.adp);
    w.leaf("Ado", c.ado);
    w.leaf("Data", c.data);
    if (c.cnt) w.leaf("Cnt", *c.cnt);
    w.leaf("Retries", 3);
    if (c.validate) {
        w.open("Validate");
        w.leaf("Data", *c.validate);
        w.leaf("DataMask", std::string("0f") + std::string(c.validate->size() - 2, '0'));
        w.leaf("Timeout", 2000);
        w.close();
    }
    w.close();
}

std::string sm_record(std::uint16_t start, std::uint16_t length, std::uint8_t control) {
    return hex_le(start, 2) + hex_le(length, 2) + hex_le(control, 1) + "00" + "01" + "00";
}

std::string fmmu_record(std::uint32_t logical, std::uint16_t length, std::uint16_t physical, bool write) {
    return hex_le(logical, 4) + hex_le(length, 2) + "00" + "07" + hex_le(physical, 2) + "00" + (write ? "02" : "01") +
           "01" + "000000";
}

struct Chunk {
    std::uint32_t offset;
    std::uint32_t length;
    int wkc;
};

// Splits [0, total) into datagram-sized chunks; WKC = slaves whose area overlaps.
std::vector<Chunk> chunks(std::uint32_t total, std::uint32_t per_slave, std::uint32_t slaves) {
    std::vector<Chunk> out;
    for (std::uint32_t at = 0; at < total; at += kMaxDatagramData) {
        const std::uint32_t length = std::min(kMaxDatagramData, total - at);
        int wkc = 0;
        for (std::uint32_t s = 0; s < slaves; ++s) {
            const std::uint32_t begin = s * per_slave;
            if (per_slave > 0 && begin < at + length && at < begin + per_slave) ++wkc;
        }
        out.push_back({at, length, wkc});
    }
    return out;
}

}  // namespace

std::string generate_eni(const GeneratedEniOptions& o) {
    const std::uint32_t total_in = o.slaves * o.input_bytes;
    const std::uint32_t total_out = o.slaves * o.output_bytes;
    Writer w;
    w.printer().PushHeader(false, true);
    w.open("EtherCATConfig");
    w.attribute("Version", "1.3");
    w.open("Config");

    w.open("Master");
    w.open("Info");
    w.leaf("Name", "ecsim generated segment");
    w.leaf("Destination", "ffffffffffff");
    w.leaf("Source", "020000000001");
    w.leaf("EtherType", "a488");
    w.close();
    w.open("InitCmds");
    write_cmd(w, {{"IP"}, "read slave count", 7, 0, 0x0130, "0000", std::nullopt, std::nullopt, true});
    write_cmd(w, {{"IP", "PI", "SI", "OI"}, "clear fmmu", 8, 0, 0x0600, std::string(512, '0'), std::nullopt,
                  std::nullopt, true});
    write_cmd(w, {{"IP"}, "clear sm", 8, 0, 0x0800, std::string(512, '0'), std::nullopt, std::nullopt, true});
    w.close();
    w.close();

    for (std::uint32_t s = 0; s < o.slaves; ++s) {
        const auto phys = static_cast<std::uint16_t>(1001 + s);
        const auto auto_inc = static_cast<std::uint16_t>((0x10000u - s) & 0xffffu);
        w.open("Slave");
        w.open("Info");
        w.leaf("Name", fmt::format("Sim IO {}", phys));
        w.leaf("PhysAddr", phys);
        w.leaf("AutoIncAddr", auto_inc);
        w.leaf("Physics", "YY");
        w.leaf("VendorId", o.vendor_id);
        w.leaf("ProductCode", o.product_code);
        w.leaf("RevisionNo", o.revision_no);
        w.leaf("SerialNo", s + 1);
        w.close();

        w.open("ProcessData");
        if (o.output_bytes > 0) {
            w.open("Send");
            w.leaf("BitStart", s * o.output_bytes * 8);
            w.leaf("BitLength", o.output_bytes * 8);
            w.close();
        }
        if (o.input_bytes > 0) {
            w.open("Recv");
            w.leaf("BitStart", s * o.input_bytes * 8);
            w.leaf("BitLength", o.input_bytes * 8);
            w.close();
        }
        auto sm = [&](const char* tag, const char* type, std::uint16_t start, std::uint8_t control, std::uint16_t pdo) {
            w.open(tag);
            w.leaf("Type", type);
            w.leaf("StartAddress", start);
            w.leaf("ControlByte", static_cast<int>(control));
            w.leaf("Enable", 1);
            w.leaf("Pdo", pdo);
            w.close();
        };
        if (o.output_bytes > 0) sm("Sm2", "Outputs", kOutputSmStart, 0x64, 0x1600);
        if (o.input_bytes > 0) sm("Sm3", "Inputs", kInputSmStart, 0x20, 0x1A00);
        auto pdo = [&](const char* tag, std::uint16_t index, int sm_index, const char* prefix, std::uint32_t bytes,
                       std::uint16_t object) {
            w.open(tag);
            w.attribute("Fixed", "1");
            w.attribute("Sm", std::to_string(sm_index));
            w.leaf("Index", fmt::format("#x{:04x}", index));
            w.leaf("Name", prefix);
            for (std::uint32_t e = 0; e < bytes; ++e) {
                w.open("Entry");
                w.leaf("Index", fmt::format("#x{:04x}", object));
                w.leaf("SubIndex", e + 1);
                w.leaf("BitLen", 8);
                w.leaf("Name", fmt::format("{} {}", prefix, e));
                w.leaf("DataType", "USINT");
                w.close();
            }
            w.close();
        };
        if (o.input_bytes > 0) pdo("TxPdo", 0x1A00, 3, "In", o.input_bytes, 0x6000);
        if (o.output_bytes > 0) pdo("RxPdo", 0x1600, 2, "Out", o.output_bytes, 0x7000);
        w.close();

        w.open("InitCmds");
        const std::string state_check = "000000000000";
        write_cmd(w, {{"IP"}, "set device state to INIT", 2, auto_inc, 0x0120, "1100", 1, std::nullopt});
        write_cmd(w, {{"IP"}, "check device state for INIT", 1, auto_inc, 0x0130, state_check, 1, "010000000000"});
        write_cmd(w, {{"IP"}, "set physical address", 2, auto_inc, 0x0010, hex_le(phys, 2), 1, std::nullopt});
        if (o.output_bytes > 0) {
            write_cmd(w, {{"IP"}, "set sm 2 (outputs)", 5, phys, 0x0810,
                          sm_record(kOutputSmStart, static_cast<std::uint16_t>(o.output_bytes), 0x64), 1, std::nullopt});
        }
        if (o.input_bytes > 0) {
            write_cmd(w, {{"IP"}, "set sm 3 (inputs)", 5, phys, 0x0818,
                          sm_record(kInputSmStart, static_cast<std::uint16_t>(o.input_bytes), 0x20), 1, std::nullopt});
        }
        write_cmd(w, {{"IP"}, "set device state to PREOP", 5, phys, 0x0120, "0200", 1, std::nullopt});
        write_cmd(w, {{"IP"}, "check device state for PREOP", 4, phys, 0x0130, state_check, 1, "020000000000"});
        if (o.output_bytes > 0) {
            write_cmd(w, {{"PS"}, "set fmmu 0 (outputs)", 5, phys, 0x0600,
                          fmmu_record(o.logical_base + s * o.output_bytes, static_cast<std::uint16_t>(o.output_bytes),
                                      kOutputSmStart, true),
                          1, std::nullopt});
        }
        if (o.input_bytes > 0) {
            write_cmd(w, {{"PS"}, "set fmmu 1 (inputs)", 5, phys, 0x0610,
                          fmmu_record(o.logical_base + s * o.input_bytes, static_cast<std::uint16_t>(o.input_bytes),
                                      kInputSmStart, false),
                          1, std::nullopt});
        }
        write_cmd(w, {{"PS"}, "set device state to SAFEOP", 5, phys, 0x0120, "0400", 1, std::nullopt});
        write_cmd(w, {{"PS"}, "check device state for SAFEOP", 4, phys, 0x0130, state_check, 1, "040000000000"});
        write_cmd(w, {{"SO"}, "set device state to OP", 5, phys, 0x0120, "0800", 1, std::nullopt});
        write_cmd(w, {{"SO"}, "check device state for OP", 4, phys, 0x0130, state_check, 1, "080000000000"});
        write_cmd(w, {{"OS"}, "set device state to SAFEOP", 5, phys, 0x0120, "0400", 1, std::nullopt});
        write_cmd(w, {{"OS"}, "check device state for SAFEOP", 4, phys, 0x0130, state_check, 1, "040000000000"});
        write_cmd(w, {{"OP", "SP"}, "set device state to PREOP", 5, phys, 0x0120, "0200", 1, std::nullopt});
        write_cmd(w, {{"OP", "SP"}, "check device state for PREOP", 4, phys, 0x0130, state_check, 1, "020000000000"});
        write_cmd(w, {{"PI", "SI", "OI"}, "set device state to INIT", 5, phys, 0x0120, "0100", 1, std::nullopt});
        write_cmd(w, {{"PI", "SI", "OI"}, "check device state for INIT", 4, phys, 0x0130, state_check, 1, "010000000000"});
        w.close();
        if (s > 0) {
            w.open("PreviousPort");
            w.attribute("Selected", "1");
            w.leaf("Port", "B");
            w.leaf("PhysAddr", phys - 1);
            w.close();
        }
        w.close();
    }

    w.open("Cyclic");
    w.leaf("CycleTime", o.cycle_time_us);
    w.open("Frame");
    auto cyclic = [&](const char* comment, int command, std::optional<std::uint32_t> addr, std::uint16_t ado,
                      std::uint32_t length, std::optional<int> cnt, std::uint32_t offset, bool states_all) {
        w.open("Cmd");
        if (states_all) w.leaf("State", "PREOP");
        w.leaf("State", "SAFEOP");
        w.leaf("State", "OP");
        w.leaf("Comment", comment);
        w.leaf("Cmd", command);
        if (addr) {
            w.leaf("Addr", *addr);
        } else {
            w.leaf("Adp", 0);
            w.leaf("Ado", ado);
        }
        w.leaf("DataLength", length);
        if (cnt) w.leaf("Cnt", *cnt);
        w.leaf("InputOffs", offset);
        w.leaf("OutputOffs", offset);
        w.close();
    };
    for (const auto& c : chunks(total_out, o.output_bytes, o.slaves)) {
        cyclic("PD; LWR", 11, o.logical_base + c.offset, 0, c.length, c.wkc, c.offset, false);
    }
    for (const auto& c : chunks(total_in, o.input_bytes, o.slaves)) {
        cyclic("PD; LRD", 10, o.logical_base + c.offset, 0, c.length, c.wkc, c.offset, false);
    }
    const std::uint32_t image = std::max(total_in, total_out);
    cyclic("MISC; BRD; AL Status Register", 7, std::nullopt, 0x0130, 2, static_cast<int>(o.slaves), image, true);
    w.close();
    w.close();

    w.open("ProcessImage");
    auto section = [&](const char* tag, const char* prefix, std::uint32_t per_slave, std::uint32_t extra) {
        w.open(tag);
        w.leaf("ByteSize", o.slaves * per_slave + extra);
        for (std::uint32_t s = 0; s < o.slaves; ++s) {
            for (std::uint32_t e = 0; e < per_slave; ++e) {
                w.open("Variable");
                w.leaf("Name", fmt::format("Sim IO {}.{} {}", 1001 + s, prefix, e));
                w.leaf("DataType", "USINT");
                w.leaf("BitSize", 8);
                w.leaf("BitOffs", (s * per_slave + e) * 8);
                w.close();
            }
        }
        w.close();
    };
    section("Inputs", "In", o.input_bytes, image + 2 - total_in);
    section("Outputs", "Out", o.output_bytes, 0);
    w.close();

    w.close();  // Config
    w.close();  // EtherCATConfig
    return w.text();
}

}  // namespace ecpair::sim
