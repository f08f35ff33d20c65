// Rules that need every slave at once.
//
// Ring positions: TwinCAT and EC-Engineer write AutoIncAddr as the 16-bit
// two's complement of the position (0, 65535, 65534...), Advantech writes the
// position itself (0, 1, 2...). A per-slave guess would be ambiguous, so the
// reading is chosen once per file: if any slave has AutoIncAddr >= 0x8000 the
// file uses two's complement, position = (0x10000 - AutoIncAddr) & 0xFFFF;
// otherwise position = AutoIncAddr. A slave without AutoIncAddr takes its
// file index as position (and the matching AutoIncAddr).
//
// Then: positions and PhysAddrs must be unique, and every PreviousPort must
// name the PhysAddr of a slave in the file.

#include <map>

#include <fmt/format.h>

#include "readers.hpp"

namespace ecpair::eni::detail {
namespace {

constexpr std::uint16_t kFirstNegative = 0x8000;

std::uint16_t twos_complement_position(std::uint16_t auto_inc_addr) {
    return static_cast<std::uint16_t>((0x10000u - auto_inc_addr) & 0xFFFFu);
}

bool file_uses_twos_complement(const std::vector<Slave>& slaves, const std::vector<Element>& elements) {
    for (std::size_t i = 0; i < slaves.size(); ++i) {
        if (elements[i].required_child("Info").has_child("AutoIncAddr") &&
            slaves[i].info.auto_inc_addr >= kFirstNegative) {
            return true;
        }
    }
    return false;
}

void derive_ring_positions(std::vector<Slave>& slaves, const std::vector<Element>& elements) {
    const bool twos_complement = file_uses_twos_complement(slaves, elements);
    std::map<std::uint16_t, std::size_t> taken;  // ring position -> slave index
    for (std::size_t i = 0; i < slaves.size(); ++i) {
        auto& info = slaves[i].info;
        const auto info_element = elements[i].required_child("Info");
        const auto auto_inc = info_element.child("AutoIncAddr");
        if (auto_inc) {
            info.ring_position = twos_complement ? twos_complement_position(info.auto_inc_addr) : info.auto_inc_addr;
        } else {
            info.ring_position = static_cast<std::uint16_t>(i);
            info.auto_inc_addr = twos_complement ? twos_complement_position(info.ring_position) : info.ring_position;
        }
        const auto [at, inserted] = taken.emplace(info.ring_position, i);
        if (!inserted) {
            const auto& where = auto_inc ? *auto_inc : info_element;
            where.fail(fmt::format("ring position {} (AutoIncAddr {}) is already taken by Slave[{}]",
                                   info.ring_position, info.auto_inc_addr, at->second + 1));
        }
    }
}

void check_unique_phys_addrs(const std::vector<Slave>& slaves, const std::vector<Element>& elements) {
    std::map<std::uint16_t, std::size_t> taken;  // PhysAddr -> slave index
    for (std::size_t i = 0; i < slaves.size(); ++i) {
        const auto [at, inserted] = taken.emplace(slaves[i].info.phys_addr, i);
        if (!inserted) {
            elements[i].required_child("Info").required_child("PhysAddr").fail(
                fmt::format("PhysAddr {} is already used by Slave[{}]", slaves[i].info.phys_addr, at->second + 1));
        }
    }
}

template <class S>
void check_previous_ports(const std::vector<S>& owners, const std::vector<Element>& elements,
                          const std::vector<Slave>& slaves) {
    std::map<std::uint16_t, std::size_t> by_phys_addr;
    for (std::size_t i = 0; i < slaves.size(); ++i) by_phys_addr.emplace(slaves[i].info.phys_addr, i);
    for (std::size_t i = 0; i < owners.size(); ++i) {
        const auto& ports = owners[i].previous_ports;
        for (std::size_t p = 0; p < ports.size(); ++p) {
            if (by_phys_addr.contains(ports[p].phys_addr)) continue;
            elements[i].children("PreviousPort")[p].required_child("PhysAddr").fail(
                fmt::format("no slave in this file has PhysAddr {}", ports[p].phys_addr));
        }
    }
}

}  // namespace

void check_slaves(std::vector<Slave>& slaves, const std::vector<Element>& elements) {
    derive_ring_positions(slaves, elements);
    check_unique_phys_addrs(slaves, elements);
    check_previous_ports(slaves, elements, slaves);
    check_hot_connect_groups(slaves, elements);
}

void check_passive_slaves(const std::vector<PassiveSlave>& passive, const std::vector<Element>& elements,
                          const std::vector<Slave>& slaves) {
    check_previous_ports(passive, elements, slaves);
}

}  // namespace ecpair::eni::detail
