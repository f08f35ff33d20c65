#include "ecpair/bus/bus_access.hpp"

#include <fmt/format.h>

namespace ecpair::bus {

std::string_view to_string(BusErrc code) {
    switch (code) {
        case BusErrc::Timeout: return "timeout";
        case BusErrc::LinkFailure: return "link failure";
        case BusErrc::MasterRedStateInactive: return "master is INACTIVE";
        case BusErrc::InvalidRequest: return "invalid request";
        case BusErrc::Cancelled: return "cancelled";
    }
    return "unknown bus error";
}

std::string SlaveAddress::to_string() const {
    return mode == Mode::Position ? fmt::format("position {}", value) : fmt::format("station 0x{:04x}", value);
}

std::vector<Expected<DatagramReply, BusError>> BusAccess::exchange_all(std::span<const DatagramRequest> requests) {
    std::vector<Expected<DatagramReply, BusError>> replies;
    replies.reserve(requests.size());
    for (const auto& request : requests) replies.push_back(exchange(request));
    return replies;
}

DatagramRequest read_request(SlaveAddress slave, std::uint16_t ado, std::size_t length) {
    DatagramRequest request;
    request.command = slave.read_command();
    request.address = wire::DatagramHeader::physical(slave.adp(), ado);
    request.data.assign(length, 0);
    return request;
}

Expected<DatagramReply, BusError> read_register(BusAccess& bus, SlaveAddress slave, std::uint16_t ado,
                                                std::size_t length) {
    return bus.exchange(read_request(slave, ado, length));
}

Expected<DatagramReply, BusError> write_register(BusAccess& bus, SlaveAddress slave, std::uint16_t ado,
                                                 std::vector<std::uint8_t> data) {
    DatagramRequest request;
    request.command = slave.write_command();
    request.address = wire::DatagramHeader::physical(slave.adp(), ado);
    request.data = std::move(data);
    return bus.exchange(request);
}

}  // namespace ecpair::bus
