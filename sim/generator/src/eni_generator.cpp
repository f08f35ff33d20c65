#include "ecpair/sim/eni_generator.hpp"

#include <algorithm>
#include <array>
#include <utility>
#include <optional>
#include <vector>

#include <fmt/format.h>
#include <tinyxml2.h>

namespace ecpair::sim {
namespace {

constexpr std::uint32_t kMaxDatagramData = 1486;
constexpr std::uint16_t kOutputSmStart = 0x1100;
constexpr std::uint16_t kInputSmStart = 0x1400;
constexpr std::uint16_t kMailboxOutStart = 0x1000;
constexpr std::uint16_t kMailboxInStart = 0x1080;
constexpr std::uint16_t kMailboxLength = 128;

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

// One slave of the generated segment, in ring (= file) order.
struct PlannedSlave {
    std::string name;
    std::uint16_t phys = 0;
    std::uint32_t product = 0;
    std::string physics = "YY";
    std::optional<std::pair<std::uint16_t, char>> previous;  // upstream PhysAddr and port
    std::uint32_t group = 0;                                 // 0: mandatory
    bool head = false;
    bool coe = false;
};

std::vector<PlannedSlave> plan_slaves(const GeneratedEniOptions& o) {
    std::vector<PlannedSlave> line;
    for (std::uint32_t s = 0; s < o.slaves; ++s) {
        PlannedSlave p;
        p.phys = static_cast<std::uint16_t>(1001 + s);
        p.product = o.product_code;
        const bool junction = s < o.groups && !o.floating;
        p.name = fmt::format("Sim {} {}", junction ? "junction" : "IO", p.phys);
        if (s < o.groups) p.physics = "YYYY";
        if (s > 0) p.previous = std::make_pair(static_cast<std::uint16_t>(p.phys - 1), 'B');
        line.push_back(p);
    }
    auto group_of = [&](std::uint32_t k) {
        std::vector<PlannedSlave> group;
        for (std::uint32_t m = 0; m < o.group_slaves; ++m) {
            PlannedSlave p;
            p.phys = static_cast<std::uint16_t>(2000 + 100 * k + m + 1);
            p.group = k;
            p.head = m == 0;
            p.coe = o.coe_groups;
            p.product = p.head ? kGroupHeadProduct : kGroupMemberProduct;
            p.name = fmt::format("Group {} {} {}", k, o.coe_groups ? "drive" : "IO", m + 1);
            if (p.head) {
                if (!o.floating) p.previous = std::make_pair(static_cast<std::uint16_t>(1000 + k), 'D');
            } else {
                p.previous = std::make_pair(static_cast<std::uint16_t>(p.phys - 1), 'B');
            }
            group.push_back(p);
        }
        return group;
    };
    if (o.groups == 0) return line;
    std::vector<PlannedSlave> all;
    for (std::uint32_t s = 0; s < line.size(); ++s) {
        all.push_back(line[s]);
        // Port D comes before port B in a frame's path: group k follows junction k.
        if (!o.floating && s < o.groups) {
            for (auto& p : group_of(s + 1)) all.push_back(p);
        }
    }
    if (o.floating) {
        for (std::uint32_t k = 1; k <= o.groups; ++k) {
            for (auto& p : group_of(k)) all.push_back(p);
        }
    }
    return all;
}

void write_identification(Writer& w, const GeneratedEniOptions& o, std::uint32_t group) {
    using Id = GeneratedEniOptions::Identification;
    if (o.identification == Id::None) return;
    const std::uint16_t ado = o.identification == Id::StationAlias       ? 0x0012
                              : o.identification == Id::ExplicitDeviceId ? 0x0134
                                                                         : static_cast<std::uint16_t>(kInputSmStart + o.input_bytes - 2);
    w.open("Identification");
    w.attribute("Value", std::to_string(kGroupIdentificationBase + group));
    w.leaf("Ado", fmt::format("#x{:04x}", ado));
    w.close();
}

void write_mailbox(Writer& w) {
    w.open("Mailbox");
    w.attribute("DataLinkLayer", "true");
    w.open("Send");
    w.leaf("Start", kMailboxOutStart);
    w.leaf("Length", kMailboxLength);
    w.close();
    w.open("Recv");
    w.leaf("Start", kMailboxInStart);
    w.leaf("Length", kMailboxLength);
    w.leaf("PollTime", 10);
    w.close();
    w.leaf("Protocol", "CoE");
    w.open("CoE");
    w.open("InitCmds");
    const std::array<std::pair<int, const char*>, 3> parameters{{{1, "1000"}, {2, "2000"}, {3, "3000"}}};
    for (const auto& [sub, data] : parameters) {
        w.open("InitCmd");
        w.leaf("Transition", "PS");
        w.leaf("Comment", fmt::format("drive parameter {}", sub));
        w.leaf("Timeout", 1000);
        w.leaf("Ccs", 1);
        w.leaf("Index", 0x8000);
        w.leaf("SubIndex", sub);
        w.leaf("Data", data);
        w.close();
    }
    w.close();
    w.close();
    w.close();
}

}  // namespace

std::optional<std::string> check_options(const GeneratedEniOptions& o) {
    if (o.slaves < 1 || o.slaves > 512) return fmt::format("--slaves must be 1..512, got {}", o.slaves);
    if (o.input_bytes > 1024 || o.output_bytes > 1024) return std::string("--input-bytes and --output-bytes must be 0..1024");
    if (o.groups > o.slaves) return fmt::format("--groups {} needs at least {} slaves in the line", o.groups, o.groups);
    if (o.groups > 0 && (o.group_slaves < 1 || o.group_slaves > 64)) {
        return fmt::format("--group-slaves must be 1..64, got {}", o.group_slaves);
    }
    if (o.groups > 0 && o.identification == GeneratedEniOptions::Identification::InputWord && o.input_bytes < 4) {
        return std::string("input-word identification needs --input-bytes of at least 4");
    }
    if (o.slaves + o.groups * o.group_slaves > 512) return std::string("at most 512 slaves in all");
    return std::nullopt;
}

std::string generate_eni(const GeneratedEniOptions& o) {
    const std::uint32_t all_slaves = o.slaves + o.groups * o.group_slaves;
    const std::uint32_t total_in = all_slaves * o.input_bytes;
    const std::uint32_t total_out = all_slaves * o.output_bytes;
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

    const auto slaves = plan_slaves(o);
    const auto count = static_cast<std::uint32_t>(slaves.size());
    for (std::uint32_t s = 0; s < slaves.size(); ++s) {
        const PlannedSlave& planned = slaves[s];
        const auto phys = planned.phys;
        const auto auto_inc = static_cast<std::uint16_t>((0x10000u - s) & 0xffffu);
        w.open("Slave");
        w.open("Info");
        w.leaf("Name", planned.name);
        w.leaf("PhysAddr", phys);
        w.leaf("AutoIncAddr", auto_inc);
        w.leaf("Physics", planned.physics);
        w.leaf("VendorId", o.vendor_id);
        w.leaf("ProductCode", planned.product);
        w.leaf("RevisionNo", o.revision_no);
        w.leaf("SerialNo", s + 1);
        if (planned.head) write_identification(w, o, planned.group);
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
        if (planned.coe) {
            auto mailbox_sm = [&](const char* tag, const char* type, std::uint16_t start, std::uint8_t control) {
                w.open(tag);
                w.leaf("Type", type);
                w.leaf("DefaultSize", kMailboxLength);
                w.leaf("StartAddress", start);
                w.leaf("ControlByte", static_cast<int>(control));
                w.leaf("Enable", 1);
                w.close();
            };
            mailbox_sm("Sm0", "MBoxOut", kMailboxOutStart, 0x26);
            mailbox_sm("Sm1", "MBoxIn", kMailboxInStart, 0x22);
        }
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
        if (planned.coe) write_mailbox(w);

        w.open("InitCmds");
        const std::string state_check = "000000000000";
        write_cmd(w, {{"IP"}, "set device state to INIT", 2, auto_inc, 0x0120, "1100", 1, std::nullopt});
        write_cmd(w, {{"IP"}, "check device state for INIT", 1, auto_inc, 0x0130, state_check, 1, "010000000000"});
        write_cmd(w, {{"IP"}, "set physical address", 2, auto_inc, 0x0010, hex_le(phys, 2), 1, std::nullopt});
        if (planned.coe) {
            write_cmd(w, {{"IP"}, "set sm 0 (mailbox out)", 5, phys, 0x0800, sm_record(kMailboxOutStart, kMailboxLength, 0x26),
                          1, std::nullopt});
            write_cmd(w, {{"IP"}, "set sm 1 (mailbox in)", 5, phys, 0x0808, sm_record(kMailboxInStart, kMailboxLength, 0x22),
                          1, std::nullopt});
        }
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
        if (planned.previous) {
            w.open("PreviousPort");
            w.attribute("Selected", "1");
            w.leaf("Port", std::string(1, planned.previous->second));
            w.leaf("PhysAddr", planned.previous->first);
            w.close();
        }
        if (planned.head) {
            w.open("HotConnect");
            w.leaf("GroupName", fmt::format("Group {}", planned.group));
            w.leaf("GroupMemberCnt", o.group_slaves);
            if (o.identification == GeneratedEniOptions::Identification::StationAlias) {
                w.open("IdentifyCmd");
                w.leaf("Comment", "check the station alias");
                w.leaf("Cmd", 1);
                w.leaf("Adp", auto_inc);
                w.leaf("Ado", 0x0012);
                w.leaf("Data", "0000");
                w.leaf("Cnt", 1);
                w.open("Validate");
                w.leaf("Data", hex_le(kGroupIdentificationBase + planned.group, 2));
                w.leaf("Timeout", 100);
                w.close();
                w.close();
            }
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
    for (const auto& c : chunks(total_out, o.output_bytes, count)) {
        cyclic("PD; LWR", 11, o.logical_base + c.offset, 0, c.length, c.wkc, c.offset, false);
    }
    for (const auto& c : chunks(total_in, o.input_bytes, count)) {
        cyclic("PD; LRD", 10, o.logical_base + c.offset, 0, c.length, c.wkc, c.offset, false);
    }
    const std::uint32_t image = std::max(total_in, total_out);
    cyclic("MISC; BRD; AL Status Register", 7, std::nullopt, 0x0130, 2, static_cast<int>(count), image, true);
    w.close();
    w.close();

    w.open("ProcessImage");
    auto section = [&](const char* tag, const char* prefix, std::uint32_t per_slave, std::uint32_t extra) {
        w.open(tag);
        w.leaf("ByteSize", count * per_slave + extra);
        for (std::uint32_t s = 0; s < count; ++s) {
            for (std::uint32_t e = 0; e < per_slave; ++e) {
                w.open("Variable");
                w.leaf("Name", fmt::format("{}.{} {}", slaves[s].name, prefix, e));
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
