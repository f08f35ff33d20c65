#pragma once
// Frames for the segment tests: built with the wire codec into a buffer
// big enough for any frame, and read back datagram by datagram.

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "ecpair/common/bytes.hpp"
#include "ecpair/wire/datagram.hpp"
#include "ecpair/wire/frame.hpp"

namespace ecpair::test {

struct TestFrame {
    std::array<std::uint8_t, wire::kMaxFrameSizeVlan> buffer{};
    std::size_t size = 0;

    Bytes bytes() { return Bytes(buffer).first(size); }
    ConstBytes bytes() const { return ConstBytes(buffer).first(size); }
};

struct DatagramSpec {
    wire::Command command = wire::Command::Brd;
    std::uint32_t address = 0;  // DatagramHeader::physical(adp, ado) or a logical address
    std::vector<std::uint8_t> data;
};

// The source MAC a master would use on its MAIN port (byte 0 = 0x00).
wire::MacAddress master_mac();

// An EtherCAT frame with these datagrams, padded to 60 bytes unless
// `unpadded` (then exactly as long as its content, as a NIC hands it over
// before padding: a 1-byte BRD is 29 bytes).
TestFrame ethercat_frame(const std::vector<DatagramSpec>& datagrams, bool unpadded = false);

// One datagram with `length` zero data bytes.
TestFrame single(wire::Command command, std::uint32_t address, std::size_t length);

// A 60-byte frame of another protocol (IPv4 EtherType, arbitrary payload).
TestFrame non_ethercat_frame();

// The n-th datagram of a frame (the frame must parse).
wire::DatagramHeader header_of(const TestFrame& frame, std::size_t n = 0);
std::uint16_t wkc_of(const TestFrame& frame, std::size_t n = 0);
std::vector<std::uint8_t> data_of(const TestFrame& frame, std::size_t n = 0);
wire::MacAddress source_of(const TestFrame& frame);

}  // namespace ecpair::test
