#include "scan_command.hpp"

#include <algorithm>
#include <ostream>

#include <boost/program_options.hpp>
#include <fmt/format.h>
#include <fmt/ostream.h>

#include "ecpair/bus/bus_scan.hpp"
#include "ecpair/bus/eni_comparison.hpp"
#include "ecpair/bus/link_bus_access.hpp"
#include "ecpair/eni/loader.hpp"
#include "ecpair/link/pcap_link.hpp"
#include "exit_codes.hpp"

namespace ecpair::ctl {
namespace {

namespace po = boost::program_options;

constexpr int kOk = 0;
constexpr int kMismatch = 1;
constexpr int kBusFailure = 3;

std::string identity_column(const bus::ScannedSlave& slave) {
    if (!slave.identity) return fmt::format("{:<47}", "(SII unreadable)");
    const auto& id = *slave.identity;
    return fmt::format("0x{:08x}  0x{:08x}  0x{:08x}  {:<10}", id.vendor_id, id.product_code, id.revision_no,
                       id.serial_no);
}

void print_table(std::ostream& out, const bus::ScanReport& report,
                 const std::vector<bus::SlaveComparison>* comparisons) {
    fmt::print(out, "{} slave(s) on the bus\n", report.responding);
    fmt::print(out, "{:>3}  {:<7} {:>5}  {:<11} {:<40} {:<10}  {:<10}  {:<10}  {:<10}{}\n", "POS", "STATION", "ALIAS",
               "STATE", "AL STATUS CODE", "VENDOR", "PRODUCT", "REVISION", "SERIAL", comparisons ? "  ENI" : "");
    for (const auto& slave : report.slaves) {
        const auto code = fmt::format("0x{:04x} {}", slave.al_status_code,
                                      wire::al_status_code_text(slave.al_status_code));
        fmt::print(out, "{:>3}  0x{:04x}  {:>5}  {:<11} {:<40} {}", slave.position, slave.station_address,
                   slave.alias, slave.al_status.to_string(), code, identity_column(slave));
        if (comparisons) {
            const auto c = std::find_if(comparisons->begin(), comparisons->end(),
                                        [&slave](const bus::SlaveComparison& e) { return e.found == &slave; });
            if (c != comparisons->end()) {
                fmt::print(out, "  {}{}", bus::to_string(c->match),
                           c->configured ? fmt::format(" '{}'", c->configured->info.name) : std::string());
            }
        }
        fmt::print(out, "\n");
        if (!slave.error.empty()) fmt::print(out, "     ! {}\n", slave.error);
    }
}

}  // namespace

int run_scan_command(const std::vector<std::string>& args, std::ostream& out, std::ostream& err) {
    std::string interface;
    std::string red_interface;
    std::string eni_path;
    po::options_description options("ecpairctl scan options");
    options.add_options()
        ("help,h", "show this help")
        ("if,i", po::value(&interface), "network interface the bus is connected to (required)")
        ("red-if", po::value(&red_interface), "the ring's other end, where frames come back in a closed redundant ring")
        ("eni,e", po::value(&eni_path), "ENI file to compare the bus with");
    po::variables_map vm;
    try {
        po::store(po::command_line_parser(args).options(options).run(), vm);
        po::notify(vm);
    } catch (const po::error& e) {
        fmt::print(err, "ecpairctl scan: {}\n{}", e.what(), fmt::streamed(options));
        return kExitUsage;
    }
    if (vm.count("help") != 0) {
        fmt::print(out, "usage: ecpairctl scan --if IF [--red-if IF] [--eni FILE]\n{}", fmt::streamed(options));
        return kOk;
    }
    if (interface.empty()) {
        fmt::print(err, "ecpairctl scan: --if is required\n{}", fmt::streamed(options));
        return kExitUsage;
    }

    std::shared_ptr<const eni::EniConfig> eni;
    if (!eni_path.empty()) {
        auto loaded = eni::load_eni_file(eni_path);
        if (!loaded) {
            fmt::print(err, "ecpairctl scan: {}\n", loaded.error().describe());
            return kExitUsage;
        }
        eni = *loaded;
    }

    auto link = link::PcapLink::open(interface, {});
    if (!link) {
        fmt::print(err, "ecpairctl scan: {}\n", link.error().message);
        return kBusFailure;
    }
    std::unique_ptr<link::PcapLink> red;
    if (!red_interface.empty()) {
        auto opened = link::PcapLink::open(red_interface, {});
        if (!opened) {
            fmt::print(err, "ecpairctl scan: {}\n", opened.error().message);
            return kBusFailure;
        }
        red = std::move(*opened);
    }
    bus::LinkBusAccess access(**link, red.get());
    auto report = bus::scan_bus(access);
    if (!report) {
        fmt::print(err, "ecpairctl scan: {}\n", report.error().message);
        return kBusFailure;
    }

    if (!eni) {
        print_table(out, *report, nullptr);
        return kOk;
    }
    const auto comparisons = bus::compare_with_eni(*report, *eni);
    print_table(out, *report, &comparisons);
    const bool matches = bus::all_match(comparisons);
    if (matches) {
        fmt::print(out, "bus matches the ENI ({} slave(s))\n", eni->slaves.size());
    } else {
        fmt::print(out, "bus does NOT match the ENI:\n");
        for (const auto& c : comparisons) {
            if (c.is_mismatch()) fmt::print(out, "  {}\n", c.describe());
        }
    }
    return matches ? kOk : kMismatch;
}

}  // namespace ecpair::ctl
