#pragma once
// Helpers for the ESC tests: example slave descriptions, frames built with
// FrameBuilder, and a Line of Esc objects that a frame passes the way a
// segment moves it (into port 0, through the processing unit, on to the next
// slave's port 0).

#include <cstdint>
#include <initializer_list>
#include <string>
#include <vector>

#include "ecpair/common/bytes.hpp"
#include "ecpair/sim/esc.hpp"
#include "ecpair/wire/command.hpp"
#include "ecpair/wire/frame.hpp"

namespace ecpair::sim::test {

// A slave with a mailbox (SM0 0x1000/128, SM1 0x1080/128, bootstrap
// mailbox), 6 bytes of outputs in SM2 at 0x1100 and 8 bytes of inputs in SM3
// at 0x1180, described by PDOs 0x1600 and 0x1A00.
EscDescription drive_description(const std::string& name = "drive");
// A slave with 1 byte of outputs in SM2 at 0x1000 and nothing else.
EscDescription io_description(const std::string& name = "io");
// A coupler: no mailbox, no process data, three ports.
EscDescription coupler_description();
// An EL2008-style terminal: no mailbox, 8 BOOL outputs in SM0 over the
// digital output register 0x0F00 (control 0x44: buffered, ECAT writes,
// watchdog trigger).
EscDescription digital_output_description(const std::string& name = "EL2008");

std::vector<std::uint8_t> le16(std::uint16_t value);
std::vector<std::uint8_t> le32(std::uint32_t value);
std::vector<std::uint8_t> bytes(std::initializer_list<int> values);

struct Datagram {
    wire::Command command = wire::Command::Nop;
    std::uint32_t address = 0;  // ADP | ADO << 16, or the logical address
    std::vector<std::uint8_t> data;
    bool circulating = false;
    std::uint16_t irq = 0;
    std::uint16_t wkc = 0;
};

// Physical addressing: position/station/broadcast address and register.
Datagram physical(wire::Command command, std::uint16_t adp, std::uint16_t ado, std::vector<std::uint8_t> data);
Datagram physical_read(wire::Command command, std::uint16_t adp, std::uint16_t ado, std::size_t length);
Datagram logical(wire::Command command, std::uint32_t address, std::vector<std::uint8_t> data);

// One EtherCAT frame in its own buffer.
class Frame {
public:
    explicit Frame(const std::vector<Datagram>& datagrams, wire::MacAddress source = {{0x01, 0x01, 0x01, 0x01, 0x01, 0x01}});

    wire::FrameView view();
    // The datagrams as they are now.
    std::vector<Datagram> datagrams();
    Datagram datagram(std::size_t index) { return datagrams().at(index); }
    wire::MacAddress source();

private:
    std::vector<std::uint8_t> buffer_;
};

// Slaves in a line: slave i's port 1 is cabled to slave i+1's port 0, the
// first port 0 to the master. Links are up as the cabling says.
class Line {
public:
    explicit Line(std::vector<EscDescription> slaves);

    Esc& operator[](std::size_t index) { return escs_.at(index); }
    std::size_t size() const { return escs_.size(); }

    // Sends the frame down the line, processing it in every slave. False when
    // a slave destroyed it.
    bool run(Frame& frame);
    // One datagram in its own frame; returns it as it came back.
    Datagram transact(const Datagram& datagram);
    // Convenience: single register accesses by station address.
    std::uint16_t fpwr(std::uint16_t station, std::uint16_t ado, const std::vector<std::uint8_t>& data);
    std::vector<std::uint8_t> fprd(std::uint16_t station, std::uint16_t ado, std::size_t length);
    // Gives slave i station address 0x1001 + i with APWR.
    void assign_station_addresses();
    std::uint64_t time_ns() const { return time_ns_; }
    std::uint64_t last_frame_seq() const { return seq_ - 1; }
    void advance(std::uint64_t ns) { time_ns_ += ns; }

private:
    std::vector<Esc> escs_;
    std::uint64_t time_ns_ = 1'000'000;
    std::uint64_t seq_ = 1;
};

inline constexpr std::uint16_t kFirstStation = 0x1001;

// Drives a drive_description() slave at `station` to `target` the way a
// master does: SMs as the SII says, then AL control; returns AL status.
std::uint8_t bring_drive_to(Line& line, std::uint16_t station, std::uint8_t target);

}  // namespace ecpair::sim::test
