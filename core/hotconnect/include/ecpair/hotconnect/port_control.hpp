#pragma once
// The loop setting of a slave's port (DL control 0x0101, two bits per port:
// 00 auto, 01 auto-close, 10 open, 11 closed; esc-facts.md §2), and which
// ports border close shuts (hot-connect.md §4): once running, every port of
// a slave on the bus where no configured slave may join, so a slave plugged
// there is not even seen -- the ports at the end of an added group too. Left
// as they are: ports where the ENI configures a slave (an absent group's
// port stays open for it to come back), ports leading to a slave of the ENI
// that is there (a floating group), and the ring's return to the master
// (a port with link and nothing found behind it when the scan ran out).

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "ecpair/bus/bus_access.hpp"
#include "ecpair/bus/topology_match.hpp"
#include "ecpair/common/expected.hpp"
#include "ecpair/eni/model.hpp"

namespace ecpair::hotconnect {

enum class LoopSetting : std::uint8_t { Auto = 0, AutoClose = 1, Open = 2, Closed = 3 };
std::string_view to_string(LoopSetting setting);
std::optional<LoopSetting> loop_setting_from(std::string_view word);  // auto, auto-close, open, closed

struct PortRef {
    std::uint16_t station = 0;
    int port = 0;  // 0..3
    friend bool operator==(const PortRef&, const PortRef&) = default;
};
std::string describe(const PortRef& port);  // "station 1001 port C"

// Reads DL control 0x0101 of the slave and writes it back with `port` changed.
Expected<void, std::string> set_loop_setting(bus::BusAccess& bus, std::uint16_t station, int port, LoopSetting setting);

// The ports border close shuts, given the last match and its scan.
std::vector<PortRef> border_ports(const eni::EniConfig& eni, const bus::ScanReport& report,
                                  const bus::TopologyMatch& match);

}  // namespace ecpair::hotconnect
