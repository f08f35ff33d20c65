// Both forms are built with fmt into one string; a slave's name is the only
// text from outside (the ENI), escaped for JSON (control characters as
// \u00XX, quotes and backslashes escaped) and, in the text form, quoted
// with control characters as blanks (a response is one line).

#include "ecpair/sim/dc_report_format.hpp"

#include <fmt/format.h>

namespace ecpair::sim {
namespace {

std::string json_string(std::string_view text) {
    std::string out = "\"";
    for (const char c : text) {
        const auto byte = static_cast<unsigned char>(c);
        if (c == '"' || c == '\\') {
            out += '\\';
            out += c;
        } else if (byte < 0x20 || byte == 0x7F) {
            out += fmt::format("\\u{:04x}", byte);
        } else {
            out += c;
        }
    }
    out += '"';
    return out;
}

std::string in_single_quotes(std::string_view text) {
    std::string out = "'";
    for (const char c : text) {
        const auto byte = static_cast<unsigned char>(c);
        out += (byte < 0x20 || byte == 0x7F) ? ' ' : c;
    }
    out += '\'';
    return out;
}

template <class T>
std::string json_or_null(const std::optional<T>& value) {
    return value ? fmt::format("{}", *value) : std::string("null");
}

std::string reference_from(const DcReport& report) {
    if (!report.reference) return "null";
    return report.reference_from_master ? "\"master\"" : "\"first_dc\"";
}

std::string signed_ns(std::int64_t ns) { return fmt::format("{:+} ns", ns); }

}  // namespace

std::string format_dc_json(const DcReport& report, const Segment& segment) {
    std::string out = fmt::format(
        "{{\"now_ns\":{},\"reference\":{},\"reference_from\":{},\"synchronised\":{},\"max_abs_deviation_ns\":{},"
        "\"worst_deviation_ns\":{},\"sync0_spread_ns\":{},\"sync0_missed\":{},\"slaves\":[",
        report.now_ns, json_or_null(report.reference), reference_from(report), report.synchronised,
        report.max_abs_deviation_ns, report.worst_deviation_ns, json_or_null(report.sync0_spread_ns),
        report.sync0_missed);
    bool first = true;
    for (const DcSlaveReport& slave : report.slaves) {
        const DcTruth& t = slave.truth;
        const bool clock = slave.powered && t.support != DcSupport::None;
        const std::optional<std::uint64_t> system_time = clock ? std::optional(t.system_time_ns) : std::nullopt;
        const auto last_at = t.last_sync0 ? std::optional(t.last_sync0->at_ns) : std::nullopt;
        const auto last_system = t.last_sync0 ? std::optional(t.last_sync0->system_ns) : std::nullopt;
        out += fmt::format(
            "{}{{\"position\":{},\"name\":{},\"dc\":\"{}\",\"powered\":{},\"deviation_ns\":{},\"drift_ppb\":{},"
            "\"system_time_ns\":{},\"sync0\":{},\"sync0_cycle_ns\":{},\"last_sync0_ns\":{},\"last_sync0_system_ns\":{},"
            "\"sync0_missed\":{},\"sync0_doubled\":{}}}",
            first ? "" : ",", slave.position, json_string(segment.slave(slave.position).description().name),
            to_string(t.support), slave.powered ? "true" : "false", json_or_null(slave.deviation_ns), t.drift_ppb,
            json_or_null(system_time), t.sync0_running ? "true" : "false", t.sync0_cycle_ns, json_or_null(last_at),
            json_or_null(last_system), t.sync0_missed, t.sync0_doubled);
        first = false;
    }
    out += "]}";
    return out;
}

std::string format_dc_text(const DcReport& report, const Segment& segment) {
    std::string out;
    if (report.reference) {
        out = fmt::format("reference=slave {} ({})", *report.reference,
                          report.reference_from_master ? "read by the master's ARMW/FRMW" : "the first DC slave");
    } else {
        out = "reference=none (no powered slave with DC)";
    }
    out += fmt::format(" synchronised={} max_abs_deviation={} ns worst_deviation={} ns sync0_spread={} sync0_missed={}",
                       report.synchronised, report.max_abs_deviation_ns, report.worst_deviation_ns,
                       report.sync0_spread_ns ? fmt::format("{} ns", *report.sync0_spread_ns) : std::string("-"),
                       report.sync0_missed);
    for (const DcSlaveReport& slave : report.slaves) {
        const DcTruth& t = slave.truth;
        out += fmt::format(" | {} {} dc={}", slave.position, in_single_quotes(segment.slave(slave.position).description().name),
                           to_string(t.support));
        if (!slave.powered) {
            out += " powered=no";
            continue;
        }
        if (t.support == DcSupport::None) continue;
        out += fmt::format(" deviation={} drift={:+.3f} ppm",
                           slave.deviation_ns ? signed_ns(*slave.deviation_ns) : std::string("-"),
                           static_cast<double>(t.drift_ppb) / 1000.0);
        if (t.sync0_running) {
            out += fmt::format(" sync0={} ns", t.sync0_cycle_ns);
            if (t.last_sync0) out += fmt::format(" last_sync0={} ns", t.last_sync0->at_ns);
        } else {
            out += " sync0=off";
        }
        if (t.sync0_missed + t.sync0_doubled != 0) {
            out += fmt::format(" missed={} doubled={}", t.sync0_missed, t.sync0_doubled);
        }
    }
    return out;
}

}  // namespace ecpair::sim
