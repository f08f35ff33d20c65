#pragma once
// The readers: one function per ENI section, each turning an Element into
// its part of the model and failing at the element that is wrong. loader.cpp
// calls them top-down (Config -> Master, Slave*, Cyclic*, ProcessImage) and
// then runs the checks that need the whole file (cross_checks.cpp).

#include <cstdint>
#include <vector>

#include "ecpair/eni/model.hpp"
#include "element.hpp"

namespace ecpair::eni::detail {

// ---- shared by InitCmds, IdentifyCmds and cyclic commands (datagram_fields.cpp)
struct DatagramAddress {
    std::uint16_t adp = 0;
    std::uint16_t ado = 0;
    std::uint32_t logical = 0;
};
// Adp/Ado for physical commands, Addr for logical ones; either form is
// accepted for both (a 32-bit Addr splits into Adp = low half, Ado = high half).
DatagramAddress read_datagram_address(const Element& cmd, wire::Command command);
// A DataLength that fits one datagram (at most wire::kMaxDatagramData).
std::uint16_t read_datagram_length(const Element& data_length);
// <Transition>* of an InitCmd; at least one when `required`.
TransitionSet read_transitions(const Element& cmd, bool required);

// ---- init_cmds.cpp
enum class EcatCmdKind { InitCmd, IdentifyCmd };
EcatCmd read_ecat_cmd(const Element& cmd, EcatCmdKind kind);
// The <InitCmds><InitCmd>* under `owner` (Master or Slave); empty when absent.
std::vector<EcatCmd> read_init_cmds(const Element& owner);

// ---- master.cpp
Master read_master(const Element& master);

// ---- slave.cpp (Info, PreviousPort, DC, HotConnect; the rest below)
Slave read_slave(const Element& slave);
// A <Slave> without PhysAddr, AutoIncAddr and InitCmds: no ESC (an EL9011 end cap).
bool is_passive_slave(const Element& slave);
PassiveSlave read_passive_slave(const Element& slave, std::size_t file_index);

// ---- process_data.cpp
ProcessData read_process_data(const Element& process_data);

// ---- mailbox.cpp
Mailbox read_mailbox(const Element& mailbox);

// ---- cyclic.cpp
Cyclic read_cyclic(const Element& cyclic);

// ---- process_image.cpp
ProcessImage read_process_image(const Element& process_image);

// ---- cross_checks.cpp: rules that need every slave at once.
// Derives SlaveInfo::ring_position, then checks that positions and PhysAddrs
// are unique and that every PreviousPort names a slave of the file.
// `elements[i]` is the <Slave> element that slaves[i] came from.
void check_slaves(std::vector<Slave>& slaves, const std::vector<Element>& elements);
// Every PreviousPort of a passive slave names a slave of the file.
void check_passive_slaves(const std::vector<PassiveSlave>& passive, const std::vector<Element>& elements,
                          const std::vector<Slave>& slaves);

// ---- register_checks.cpp: register InitCmds whose data cannot be right
// (FMMU records, station address, AL control) are refused at their InitCmd.
// Under an <EncryptedEtherCATConfig> root a station address or AL control
// that does not decode means an encrypted body (refused as such), FMMU
// records alone a warning. `slave_elements[i]` is the <Slave> of config.slaves[i].
void check_register_init_cmds(const EniConfig& config, const Element& root, const Element& config_element,
                              const std::vector<Element>& slave_elements);

// ---- hot_connect_checks.cpp: the rules of Hot-Connect groups (run by check_slaves).
void check_hot_connect_groups(const std::vector<Slave>& slaves, const std::vector<Element>& elements);

}  // namespace ecpair::eni::detail
