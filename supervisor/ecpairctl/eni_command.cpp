// `ecpairctl eni FILE`. The loader does all the validating; this file only
// decides what a person wants to see of a valid ENI and lays it out in
// aligned columns:
//   header           file, root element/version, master, content hash
//   slave table      ring position, PhysAddr, name, identity, process data
//                    bits, mailbox protocols, DC role; then the passive
//                    terminals (no ESC), which are no part of the ring
//   cyclic table     every cyclic datagram with its states and offsets
//   process image    sizes and variable counts
//   Hot-Connect      groups, when the file has any
//   remarks          what matters for cable redundancy (LRW)
// Names are printed with control characters escaped, so "RDM\n" stays on
// its row.

#include "eni_command.hpp"

#include <algorithm>
#include <ostream>
#include <string_view>

#include <fmt/format.h>
#include <fmt/ostream.h>

#include "ecpair/eni/loader.hpp"

namespace ecpair::ctl {
namespace {

constexpr int kValid = 0;
constexpr int kInvalid = 2;

constexpr std::string_view kUsage =
    "usage: ecpairctl eni FILE\n"
    "Validates an ENI file (EtherCAT Network Information) and summarises it.\n"
    "Exit status: 0 valid, 2 invalid file or wrong arguments.\n";

// A plain text table: columns as wide as their widest cell (counted in UTF-8
// code points), numbers right-aligned, text left-aligned.
class TextTable {
public:
    enum class Align { Left, Right };
    struct Column {
        std::string title;
        Align align;
    };

    explicit TextTable(std::vector<Column> columns) : columns_(std::move(columns)) {}

    void add_row(std::vector<std::string> cells) { rows_.push_back(std::move(cells)); }

    void print(std::ostream& out, std::string_view indent) const {
        std::vector<std::size_t> widths;
        for (const auto& column : columns_) widths.push_back(display_width(column.title));
        for (const auto& row : rows_) {
            for (std::size_t c = 0; c < row.size() && c < widths.size(); ++c) {
                widths[c] = std::max(widths[c], display_width(row[c]));
            }
        }
        std::vector<std::string> titles;
        for (const auto& column : columns_) titles.push_back(column.title);
        print_row(out, indent, titles, widths);
        for (const auto& row : rows_) print_row(out, indent, row, widths);
    }

private:
    static std::size_t display_width(std::string_view text) {
        return static_cast<std::size_t>(
            std::count_if(text.begin(), text.end(), [](char c) { return (static_cast<unsigned char>(c) & 0xC0) != 0x80; }));
    }

    void print_row(std::ostream& out, std::string_view indent, const std::vector<std::string>& cells,
                   const std::vector<std::size_t>& widths) const {
        std::string line(indent);
        for (std::size_t c = 0; c < columns_.size(); ++c) {
            const std::string& cell = c < cells.size() ? cells[c] : std::string();
            const std::string padding(widths[c] - display_width(cell), ' ');
            const bool last = c + 1 == columns_.size();
            if (c != 0) line += "  ";
            if (columns_[c].align == Align::Right) {
                line += padding + cell;
            } else {
                line += cell;
                if (!last) line += padding;
            }
        }
        out << line << '\n';
    }

    std::vector<Column> columns_;
    std::vector<std::vector<std::string>> rows_;
};

std::string printable(std::string_view text) {
    std::string out;
    for (const char c : text) {
        if (c == '\n') {
            out += "\\n";
        } else if (c == '\r') {
            out += "\\r";
        } else if (c == '\t') {
            out += "\\t";
        } else if (static_cast<unsigned char>(c) < 0x20) {
            out += '?';
        } else {
            out += c;
        }
    }
    return out;
}

std::string or_dash(const std::string& text) {
    return text.empty() ? "-" : text;
}

std::string protocols_text(const eni::Slave& slave) {
    if (!slave.mailbox || slave.mailbox->protocols == 0) return "-";
    static constexpr std::pair<eni::MailboxProtocol, std::string_view> kNames[] = {
        {eni::kCoE, "CoE"}, {eni::kEoE, "EoE"}, {eni::kFoE, "FoE"},
        {eni::kSoE, "SoE"}, {eni::kAoE, "AoE"}, {eni::kVoE, "VoE"}};
    std::string out;
    for (const auto& [bit, name] : kNames) {
        if ((slave.mailbox->protocols & bit) == 0) continue;
        if (!out.empty()) out += ',';
        out += name;
    }
    return out;
}

std::string dc_text(const eni::Slave& slave) {
    if (!slave.dc) return "-";
    if (slave.dc->reference_clock) return "ref clock";
    if (slave.dc->cycle_time0_ns.value_or(0) != 0) return "sync0";
    return "-";
}

std::string identification_text(const eni::Slave& slave) {
    const auto& id = slave.info.identification;
    if (!id) return "-";
    return id->value ? fmt::format("0x{:04x}={}", id->ado, *id->value) : fmt::format("0x{:04x}", id->ado);
}

std::string bits_text(const std::optional<eni::BitRange>& range) {
    return range ? std::to_string(range->bit_length) : "-";
}

std::string states_text(const eni::StateSet& states) {
    std::string out;
    for (const auto state : {eni::SlaveState::Init, eni::SlaveState::Preop, eni::SlaveState::Boot,
                             eni::SlaveState::Safeop, eni::SlaveState::Op}) {
        if (!states.contains(state)) continue;
        if (!out.empty()) out += ',';
        out += eni::to_string(state);
    }
    return out;
}

std::string address_text(const eni::CyclicCmd& cmd) {
    if (wire::addressing_of(cmd.command) == wire::Addressing::Logical) {
        return fmt::format("logical 0x{:08x}", cmd.logical_address);
    }
    return fmt::format("0x{:04x}:0x{:04x}", cmd.adp, cmd.ado);
}

std::string optional_number(const std::optional<std::uint16_t>& value) {
    return value ? std::to_string(*value) : "-";
}

std::string optional_number(const std::optional<std::uint32_t>& value) {
    return value ? std::to_string(*value) : "-";
}

void print_header(std::ostream& out, const eni::EniConfig& eni) {
    fmt::print(out, "ENI       {}\n", eni.source_path);
    fmt::print(out, "root      <{}>{}\n", eni.root_element,
               eni.version ? fmt::format(" Version {}", *eni.version) : std::string(" (no Version)"));
    fmt::print(out, "master    {}\n", or_dash(printable(eni.master.info.name)));
    fmt::print(out, "hash      fnv1a64 {:016x}\n", eni.content_hash);
}

void print_slaves(std::ostream& out, const eni::EniConfig& eni) {
    fmt::print(out, "\n{} slave(s)\n", eni.slaves.size());
    if (eni.slaves.empty()) return;
    using A = TextTable::Align;
    TextTable table({{"POS", A::Right}, {"PHYS", A::Right}, {"NAME", A::Left}, {"VENDOR", A::Left},
                     {"PRODUCT", A::Left}, {"REVISION", A::Left}, {"SERIAL", A::Right}, {"IDENT", A::Left},
                     {"IN BITS", A::Right}, {"OUT BITS", A::Right}, {"MAILBOX", A::Left}, {"DC", A::Left}});
    for (const auto& slave : eni.slaves) {
        const auto& info = slave.info;
        table.add_row({std::to_string(info.ring_position), std::to_string(info.phys_addr), or_dash(printable(info.name)),
                       fmt::format("0x{:08x}", info.vendor_id), fmt::format("0x{:08x}", info.product_code),
                       fmt::format("0x{:08x}", info.revision_no), optional_number(info.serial_no),
                       identification_text(slave), bits_text(slave.process_data.recv),
                       bits_text(slave.process_data.send), protocols_text(slave), dc_text(slave)});
    }
    table.print(out, "  ");

    std::size_t esc = 0;
    std::size_t coe = 0;
    for (const auto& slave : eni.slaves) {
        esc += slave.init_cmds.size();
        if (slave.mailbox) coe += slave.mailbox->coe_init_cmds.size();
    }
    fmt::print(out, "init commands: {} master, {} slave register, {} CoE\n", eni.master.init_cmds.size(), esc, coe);
    for (const auto& passive : eni.passive_slaves) {
        const std::string where = passive.previous_ports.empty()
                                      ? std::string()
                                      : fmt::format(" behind station {} port {}", passive.previous_ports.front().phys_addr,
                                                    passive.previous_ports.front().port);
        fmt::print(out, "passive terminal (no ESC, not in the ring): {}{} product {}\n", or_dash(printable(passive.name)), where,
                   passive.product_code ? fmt::format("0x{:08x}", *passive.product_code) : std::string("-"));
    }
}

void print_cyclic(std::ostream& out, const eni::EniConfig& eni) {
    for (std::size_t c = 0; c < eni.cyclic.size(); ++c) {
        const auto& cyclic = eni.cyclic[c];
        fmt::print(out, "\ncyclic{}: cycle time {}, {} frame(s)\n", eni.cyclic.size() > 1 ? fmt::format(" {}", c + 1) : "",
                   cyclic.cycle_time_us ? fmt::format("{} us", *cyclic.cycle_time_us) : std::string("not given"),
                   cyclic.frames.size());
        using A = TextTable::Align;
        TextTable table({{"FRAME", A::Right}, {"CMD", A::Left}, {"STATES", A::Left}, {"ADDRESS", A::Left},
                         {"LENGTH", A::Right}, {"CNT", A::Right}, {"IN OFFS", A::Right}, {"OUT OFFS", A::Right}});
        bool any = false;
        for (std::size_t f = 0; f < cyclic.frames.size(); ++f) {
            for (const auto& cmd : cyclic.frames[f].cmds) {
                table.add_row({std::to_string(f + 1), wire::to_string(cmd.command), states_text(cmd.states),
                               address_text(cmd), std::to_string(cmd.data_length), optional_number(cmd.expected_wkc),
                               optional_number(cmd.input_offset), optional_number(cmd.output_offset)});
                any = true;
            }
        }
        if (any) table.print(out, "  ");
    }
}

void print_process_image(std::ostream& out, const eni::EniConfig& eni) {
    if (!eni.process_image) {
        fmt::print(out, "\nprocess image: not described\n");
        return;
    }
    const auto section = [](const std::optional<eni::ProcessImageSection>& s) {
        return s ? fmt::format("{} bytes, {} variable(s)", s->byte_size, s->variables.size()) : std::string("-");
    };
    fmt::print(out, "\nprocess image\n  inputs   {}\n  outputs  {}\n", section(eni.process_image->inputs),
               section(eni.process_image->outputs));
}

void print_hot_connect(std::ostream& out, const eni::EniConfig& eni) {
    using A = TextTable::Align;
    TextTable table({{"HEAD POS", A::Right}, {"HEAD PHYS", A::Right}, {"GROUP", A::Left}, {"MEMBERS", A::Right},
                     {"IDENTIFY CMDS", A::Right}});
    std::size_t groups = 0;
    for (const auto& slave : eni.slaves) {
        if (!slave.hot_connect) continue;
        const auto& hc = *slave.hot_connect;
        table.add_row({std::to_string(slave.info.ring_position), std::to_string(slave.info.phys_addr),
                       or_dash(printable(hc.group_name)), std::to_string(hc.group_member_count),
                       std::to_string(hc.identify_cmds.size())});
        ++groups;
    }
    if (groups == 0) {
        fmt::print(out, "\nhot-connect groups: none\n");
        return;
    }
    fmt::print(out, "\n{} hot-connect group(s)\n", groups);
    table.print(out, "  ");
}

void print_remarks(std::ostream& out, const eni::EniConfig& eni) {
    std::size_t lrw = 0;
    for (const auto& cyclic : eni.cyclic) {
        for (const auto& frame : cyclic.frames) {
            lrw += static_cast<std::size_t>(std::count_if(frame.cmds.begin(), frame.cmds.end(), [](const eni::CyclicCmd& c) {
                return c.command == wire::Command::Lrw;
            }));
        }
    }
    fmt::print(out, "\n");
    if (eni.uses_logical_read_write()) {
        fmt::print(out,
                   "warning: the cyclic frames use LRW ({} command(s)); cable redundancy refuses LRW:\n"
                   "         export the ENI with separate LRD (inputs) and LWR (outputs) commands\n",
                   lrw);
    } else {
        fmt::print(out, "cable redundancy: no LRW in the cyclic frames\n");
    }
    fmt::print(out, "valid\n");
}

}  // namespace

int run_eni_command(const std::vector<std::string>& args, std::ostream& out, std::ostream& err) {
    if (args.size() == 1 && (args[0] == "-h" || args[0] == "--help")) {
        out << kUsage;
        return kValid;
    }
    if (args.size() != 1 || args[0].empty() || args[0].front() == '-') {
        err << "ecpairctl eni: expected exactly one ENI file\n" << kUsage;
        return kInvalid;
    }
    const auto loaded = eni::load_eni_file(args[0]);
    if (!loaded) {
        fmt::print(err, "ecpairctl eni: {}\n", loaded.error().describe());
        return kInvalid;
    }
    const auto& eni = **loaded;
    print_header(out, eni);
    print_slaves(out, eni);
    print_cyclic(out, eni);
    print_process_image(out, eni);
    print_hot_connect(out, eni);
    print_remarks(out, eni);
    return kValid;
}

}  // namespace ecpair::ctl
