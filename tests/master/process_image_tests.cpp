#include <catch2/catch.hpp>

#include "ecpair/master/process_image.hpp"

using namespace ecpair;
using namespace ecpair::master;

namespace {

eni::ProcessImage layout() {
    eni::ProcessImage pi;
    eni::ProcessImageSection in;
    in.byte_size = 8;
    in.variables.push_back({"Drive.Status word", "", "UINT", 16, 16});
    in.variables.push_back({"Io.Input 3", "", "BOOL", 1, 35});
    in.variables.push_back({"Blob", "", "", 128, 0});  // too wide for typed access
    eni::ProcessImageSection out;
    out.byte_size = 4;
    out.variables.push_back({"Drive.Control word", "", "UINT", 16, 0});
    out.variables.push_back({"Io.Nibble", "", "", 4, 18});
    pi.inputs = in;
    pi.outputs = out;
    return pi;
}

}  // namespace

TEST_CASE("variables are found by name and sized from the ENI", "[image]") {
    ProcessImage image(0, 0, layout());
    CHECK(image.inputs().size() == 16);  // the 128-bit blob needs 16 bytes
    CHECK(image.outputs().size() == 4);
    REQUIRE(image.find("Drive.Status word"));
    CHECK(image.find("Drive.Status word")->section == ImageSection::Inputs);
    CHECK(image.find("Drive.Control word")->section == ImageSection::Outputs);
    CHECK_FALSE(image.find("Blob"));
    CHECK_FALSE(image.find("nothing"));
    CHECK(image.variables(ImageSection::Inputs).size() == 2);
}

TEST_CASE("typed access is little-endian and bit-exact", "[image]") {
    ProcessImage image(0, 0, layout());
    const auto status = *image.find("Drive.Status word");
    image.write_bits(status, 0x1234);
    CHECK(image.inputs()[2] == 0x34);
    CHECK(image.inputs()[3] == 0x12);
    CHECK(image.read_bits(status) == 0x1234);

    const auto bit = *image.find("Io.Input 3");
    image.write_bits(bit, 1);
    CHECK(image.inputs()[4] == 0x08);
    image.write_bits(bit, 0);
    CHECK(image.inputs()[4] == 0x00);

    const auto nibble = *image.find("Io.Nibble");  // bits 18..21: straddles nothing, but not byte aligned
    image.outputs()[2] = 0xff;
    image.write_bits(nibble, 0x5);
    CHECK(image.outputs()[2] == 0xd7);  // 1101 0111: bits 2..5 = 0101
    CHECK(image.read_bits(nibble) == 0x5);
}

TEST_CASE("bits can straddle byte boundaries", "[image]") {
    std::array<std::uint8_t, 4> bytes{};
    write_bits(bytes, 6, 12, 0xabc);
    CHECK(read_bits(bytes, 6, 12) == 0xabc);
    CHECK(bytes[0] == 0x00);  // 0xabc << 6 = 0x2af00
    CHECK(bytes[1] == 0xaf);
    CHECK(bytes[2] == 0x02);
}
