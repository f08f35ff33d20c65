// The slaves' section: one row per configured slave, then the process image
// variables asked for (--variables N).

#include <ostream>

#include <fmt/format.h>
#include <fmt/ostream.h>

#include "status_sections.hpp"

namespace ecpair::ctl {

void slaves_table(std::ostream& out, const control::StatusReply& s) {
    fmt::print(out, "  {:>3}  {:<7}  {:<8}  {:<11}  {}\n", "POS", "STATION", "PRESENT", "STATE", "NAME");
    for (const auto& slave : s.slaves()) {
        fmt::print(out, "  {:>3}  {:<7}  {:<8}  {:<11}  {}{}\n", slave.position(), slave.station_address(),
                   slave.present() ? "yes" : "no", slave.al_state(), slave.name(),
                   slave.al_status_code() != 0 ? fmt::format(" (AL status code 0x{:04x})", slave.al_status_code())
                                               : std::string());
    }
    auto variables = [&out](const char* title, const auto& list) {
        if (list.empty()) return;
        fmt::print(out, "  {}:\n", title);
        for (const auto& v : list) fmt::print(out, "    {:<48} 0x{:0{}x}\n", v.name(), v.value(), (v.bit_size() + 3) / 4);
    };
    variables("inputs", s.inputs());
    variables("outputs", s.outputs());
}

void slaves_json(JsonWriter& json, const control::StatusReply& s) {
    json.key("slaves").begin_array();
    for (const auto& slave : s.slaves()) {
        json.begin_object().key("position").value(slave.position()).key("name").value(slave.name());
        json.key("station_address").value(slave.station_address()).key("present").value(slave.present());
        json.key("al_state").value(slave.al_state()).key("al_status_code").value(slave.al_status_code()).end_object();
    }
    json.end_array();
    auto variables = [&json](const char* key, const auto& list) {
        json.key(key).begin_array();
        for (const auto& v : list) {
            json.begin_object().key("name").value(v.name()).key("value").value(v.value());
            json.key("bit_size").value(v.bit_size()).end_object();
        }
        json.end_array();
    };
    variables("inputs", s.inputs());
    variables("outputs", s.outputs());
}

}  // namespace ecpair::ctl
