#include "pair_view.hpp"

#include <algorithm>
#include <ostream>

#include <fmt/format.h>
#include <fmt/ostream.h>

#include "status_sections.hpp"

namespace ecpair::ctl {
namespace {

std::string member_name(const PairMember& m) { return m.status ? m.status->name() : m.socket; }

bool is_active(const PairMember& m) { return m.status && m.status->redundancy().red_state() == "ACTIVE"; }

std::size_t slaves_in_op(const control::StatusReply& s) {
    return static_cast<std::size_t>(std::count_if(s.slaves().begin(), s.slaves().end(),
                                                  [](const auto& slave) { return slave.al_state() == "OP"; }));
}

std::string standby_quality(const control::StatusReply& s) {
    const auto& r = s.redundancy();
    if (!r.partner_mismatch().empty()) return "NOT a standby: partner differs (" + r.partner_mismatch() + ")";
    if (forced_standby(s)) return "forced standby";
    if (s.link_guard().links_down()) return "links down by its link guard";
    if (!r.partner_seen()) return "does NOT see the ACTIVE's frames";
    return fmt::format("hot standby (mirrored cycle {})", r.mirrored_cycle());
}

// The rows of the table: a label and a function of one member's status.
struct Row {
    const char* label;
    std::string (*cell)(const control::StatusReply& s);
};

const Row kRows[] = {
    {"role", [](const control::StatusReply& s) {
         return s.redundancy().enabled() ? s.redundancy().red_state() : std::string("not a pair member");
     }},
    {"master", [](const control::StatusReply& s) { return s.master_state(); }},
    {"partner", [](const control::StatusReply& s) {
         const auto& r = s.redundancy();
         std::string text = r.partner_seen() ? "seen" : "NOT seen";
         if (r.red_state() == "INACTIVE") text += fmt::format(", mirrored {}", r.mirrored_cycle());
         if (!r.partner_mismatch().empty()) text += ", DIFFERS";
         return text;
     }},
    {"links", [](const control::StatusReply& s) {
         return fmt::format("MAIN {}, RED {}", s.main_link_up() ? "up" : "DOWN", s.red_link_up() ? "up" : "DOWN");
     }},
    {"ring", [](const control::StatusReply& s) { return s.ring_state(); }},
    {"cycles", [](const control::StatusReply& s) {
         return fmt::format("{} ({} late)", s.timing().cycles(), s.timing().late());
     }},
    {"link guard", [](const control::StatusReply& s) {
         const auto& g = s.link_guard();
         if (!g.enabled()) return std::string("off");
         return std::string(!g.running() ? "NOT RUNNING" : g.links_down() ? "LINKS DOWN" : "on");
     }},
    {"slaves in OP", [](const control::StatusReply& s) {
         return fmt::format("{}/{}", slaves_in_op(s), s.slaves_size());
     }},
};

}  // namespace

std::string pair_verdict(const std::vector<PairMember>& members) {
    std::vector<std::string> unreachable;
    for (const auto& m : members) {
        if (!m.status) unreachable.push_back("unreachable: " + m.error);
    }
    std::vector<const PairMember*> active;
    for (const auto& m : members) {
        if (is_active(m)) active.push_back(&m);
    }
    std::string verdict;
    if (active.size() > 1) {
        verdict = fmt::format("TWO ACTIVE masters: {} and {} both drive the bus", member_name(*active[0]),
                              member_name(*active[1]));
    } else if (active.empty()) {
        verdict = unreachable.size() == members.size() ? std::string("no member answers")
                                                       : std::string("NO ACTIVE master: nobody drives the slaves");
    } else {
        verdict = fmt::format("{} ACTIVE", member_name(*active[0]));
        for (const auto& m : members) {
            if (&m == active[0] || !m.status) continue;
            verdict += fmt::format("; {} {}, {}", member_name(m), m.status->redundancy().red_state(),
                                   standby_quality(*m.status));
        }
    }
    for (const auto& u : unreachable) verdict += "; " + u;
    return verdict;
}

void print_pair_table(std::ostream& out, const std::vector<PairMember>& members) {
    std::vector<std::vector<std::string>> columns;
    std::size_t width = 0;
    for (const auto& m : members) {
        std::vector<std::string> column{member_name(m)};
        for (const auto& row : kRows) column.push_back(m.status ? row.cell(*m.status) : std::string("-"));
        for (const auto& cell : column) width = std::max(width, cell.size());
        columns.push_back(std::move(column));
    }
    width = std::min<std::size_t>(width + 2, 40);
    for (std::size_t r = 0; r <= std::size(kRows); ++r) {
        fmt::print(out, "{:<14}", r == 0 ? "pair" : kRows[r - 1].label);
        for (const auto& column : columns) fmt::print(out, "{:<{}}", column[r], width);
        fmt::print(out, "\n");
    }
    fmt::print(out, "verdict: {}\n", pair_verdict(members));
}

void write_pair_json(JsonWriter& json, const std::vector<PairMember>& members) {
    json.begin_object().key("members").begin_array();
    std::size_t active = 0;
    const PairMember* the_active = nullptr;
    for (const auto& m : members) {
        if (m.status) {
            // The member's own status object, plus where it was asked.
            json.begin_object().key("socket").value(m.socket).key("reachable").value(true).key("status");
            write_status_json(json, *m.status);
            json.end_object();
        } else {
            json.begin_object().key("socket").value(m.socket).key("reachable").value(false);
            json.key("error").value(m.error).end_object();
        }
        if (is_active(m)) {
            ++active;
            the_active = &m;
        }
    }
    json.end_array();
    json.key("active_count").value(static_cast<std::uint64_t>(active)).key("active");
    if (active == 1) {
        json.value(member_name(*the_active));
    } else {
        json.null();
    }
    json.key("verdict").value(pair_verdict(members)).end_object();
}

}  // namespace ecpair::ctl
