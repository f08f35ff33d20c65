// Addressing, data semantics and working counters of every command
// (esc-facts.md §1), through one or a few ESCs in a line.

#include <catch2/catch.hpp>

#include "esc_test_support.hpp"

using namespace ecpair;
using namespace ecpair::sim;
using namespace ecpair::sim::test;
using wire::Command;

namespace {

std::uint16_t adp_of(const Datagram& d) { return static_cast<std::uint16_t>(d.address & 0xFFFF); }

Line three_drives() { return Line({drive_description("a"), drive_description("b"), drive_description("c")}); }

}  // namespace

TEST_CASE("auto-increment commands address the slave that receives ADP 0 and increment ADP everywhere") {
    Line line = three_drives();
    line.assign_station_addresses();
    REQUIRE(line[0].station_address() == 0x1001);
    REQUIRE(line[1].station_address() == 0x1002);
    REQUIRE(line[2].station_address() == 0x1003);

    const Datagram read = line.transact(physical_read(Command::Aprd, 0xFFFF, 0x0010, 2));
    CHECK(read.wkc == 1);
    CHECK(read.data == le16(0x1002));
    CHECK(adp_of(read) == 0x0002);  // 0xFFFF + 3, wrapping at 16 bits

    const Datagram write = line.transact(physical(Command::Apwr, 0xFFFE, 0x0200, le16(0x0004)));
    CHECK(write.wkc == 1);
    CHECK(adp_of(write) == 0x0001);
    CHECK(line[2].read_memory(0x0200, 2) == le16(0x0004));
    CHECK(line[1].read_memory(0x0200, 2) == le16(0x0000));

    const Datagram none = line.transact(physical_read(Command::Aprd, 0x0005, 0x0010, 2));
    CHECK(none.wkc == 0);
    CHECK(none.data == le16(0));
    CHECK(adp_of(none) == 0x0008);
}

TEST_CASE("broadcast reads OR every slave's memory into the data, count every slave and increment ADP") {
    Line line = three_drives();
    line.assign_station_addresses();
    const Datagram brd = line.transact(physical_read(Command::Brd, 0, 0x0010, 2));
    CHECK(brd.wkc == 3);
    CHECK(brd.data == le16(0x1001 | 0x1002 | 0x1003));
    CHECK(adp_of(brd) == 3);

    const Datagram type = line.transact(physical_read(Command::Brd, 0, 0x0000, 2));
    CHECK(type.wkc == 3);  // SOEM counts slaves like this
    CHECK(type.data == bytes({0x11, 0x00}));

    const Datagram bwr = line.transact(physical(Command::Bwr, 0, 0x0200, le16(0x0004)));
    CHECK(bwr.wkc == 3);
    CHECK(adp_of(bwr) == 3);
    for (std::size_t i = 0; i < line.size(); ++i) CHECK(line[i].read_memory(0x0200, 2) == le16(0x0004));
}

TEST_CASE("configured-address commands match the station address, or the alias only when enabled") {
    auto aliased = drive_description("aliased");
    aliased.alias = 0x0BEE;
    Line line({drive_description("a"), aliased});
    line.assign_station_addresses();
    REQUIRE(line[1].station_alias() == 0x0BEE);

    CHECK(line.transact(physical_read(Command::Fprd, 0x1002, 0x0010, 2)).wkc == 1);
    CHECK(line.transact(physical_read(Command::Fprd, 0x0BEE, 0x0010, 2)).wkc == 0);
    CHECK(line.transact(physical_read(Command::Fprd, 0x7777, 0x0010, 2)).wkc == 0);

    // 0x0100 bit 24 (0x0103 bit 0) enables the alias.
    CHECK(line.fpwr(0x1002, 0x0103, bytes({0x01})) == 1);
    const Datagram by_alias = line.transact(physical_read(Command::Fprd, 0x0BEE, 0x0010, 2));
    CHECK(by_alias.wkc == 1);
    CHECK(by_alias.data == le16(0x1002));
    CHECK(adp_of(by_alias) == 0x0BEE);  // FP commands leave ADP alone
    // The station address still works.
    CHECK(line.transact(physical_read(Command::Fprd, 0x1002, 0x0010, 2)).wkc == 1);
}

TEST_CASE("read-write commands read first and write to ADO plus the read/write offset") {
    Line line = three_drives();
    line.assign_station_addresses();

    SECTION("FPRW: +3 when both halves succeed, the write uses the data as it arrived") {
        line[1].write_memory(0x0F80, bytes({0x11, 0x22}));
        const Datagram rw = line.transact(physical(Command::Fprw, 0x1002, 0x0F80, bytes({0xAA, 0xBB})));
        CHECK(rw.wkc == 3);
        CHECK(rw.data == bytes({0x11, 0x22}));
        CHECK(line[1].read_memory(0x0F80, 2) == bytes({0xAA, 0xBB}));
    }
    SECTION("APRW with an offset in 0x0108 writes elsewhere") {
        CHECK(line.fpwr(0x1001, 0x0108, le16(0x0010)) == 1);
        line[0].write_memory(0x0F80, bytes({0x01, 0x02}));
        const Datagram rw = line.transact(physical(Command::Aprw, 0, 0x0F80, bytes({0x0A, 0x0B})));
        CHECK(rw.wkc == 3);
        CHECK(rw.data == bytes({0x01, 0x02}));
        CHECK(line[0].read_memory(0x0F80, 2) == bytes({0x01, 0x02}));
        CHECK(line[0].read_memory(0x0F90, 2) == bytes({0x0A, 0x0B}));
    }
    SECTION("BRW: each slave ORs its memory in and writes the data as it reached it") {
        for (std::size_t i = 0; i < line.size(); ++i) line[i].write_memory(0x0F80, bytes({1 << i}));
        const Datagram rw = line.transact(physical(Command::Brw, 0, 0x0F80, bytes({0x40})));
        CHECK(rw.wkc == 9);
        CHECK(rw.data == bytes({0x40 | 0x01 | 0x02 | 0x04}));
        CHECK(line[0].read_memory(0x0F80, 1) == bytes({0x40}));
        CHECK(line[1].read_memory(0x0F80, 1) == bytes({0x41}));
        CHECK(line[2].read_memory(0x0F80, 1) == bytes({0x43}));
    }
    SECTION("each half counts on its own: +1 read only, +2 write only") {
        // Write address past the 8 KiB of process RAM: only the read succeeds.
        CHECK(line.fpwr(0x1001, 0x0108, le16(0x4000)) == 1);
        CHECK(line.transact(physical(Command::Fprw, 0x1001, 0x0F80, bytes({1}))).wkc == 1);
        // Read past the RAM, write (0x3000 + 0xE000, 16-bit) into it: only the write.
        CHECK(line.fpwr(0x1001, 0x0108, le16(0xE000)) == 1);
        CHECK(line.transact(physical(Command::Fprw, 0x1001, 0x3000, bytes({0x77}))).wkc == 2);
        CHECK(line[0].read_memory(0x1000, 1) == bytes({0x77}));
    }
    SECTION("read-only register bytes are accessible: both halves count, nothing changes") {
        const Datagram rw = line.transact(physical(Command::Fprw, 0x1001, 0x0000, bytes({0x55})));
        CHECK(rw.wkc == 3);
        CHECK(rw.data == bytes({0x11}));
        CHECK(line[0].read_memory(0x0000, 1) == bytes({0x11}));
    }
}

TEST_CASE("ARMW and FRMW: the addressed slave reads, all others write, each counts 1") {
    Line line = three_drives();
    line.assign_station_addresses();
    for (std::size_t i = 0; i < line.size(); ++i) line[i].write_memory(0x0F80, le32(static_cast<std::uint32_t>(0x100U * (i + 1))));

    const Datagram armw = line.transact(physical(Command::Armw, 0xFFFF, 0x0F80, le32(0xDEAD)));
    CHECK(armw.wkc == 3);
    CHECK(armw.data == le32(0x200));  // read by slave 2
    CHECK(adp_of(armw) == 2);
    CHECK(line[0].read_memory(0x0F80, 4) == le32(0xDEAD));  // written before the reader
    CHECK(line[1].read_memory(0x0F80, 4) == le32(0x200));
    CHECK(line[2].read_memory(0x0F80, 4) == le32(0x200));  // written with the value read

    const Datagram frmw = line.transact(physical(Command::Frmw, 0x1001, 0x0F80, le32(0)));
    CHECK(frmw.wkc == 3);
    CHECK(frmw.data == le32(0xDEAD));
    CHECK(adp_of(frmw) == 0x1001);
    CHECK(line[1].read_memory(0x0F80, 4) == le32(0xDEAD));
    CHECK(line[2].read_memory(0x0F80, 4) == le32(0xDEAD));
}

TEST_CASE("NOP and reserved commands are left alone") {
    Line line = three_drives();
    Datagram nop = physical(Command::Nop, 0, 0x4155, bytes({1, 2, 3}));
    const Datagram after = line.transact(nop);
    CHECK(after.wkc == 0);
    CHECK(after.data == bytes({1, 2, 3}));
    CHECK(after.address == nop.address);

    Datagram reserved = physical(static_cast<Command>(0x1F), 0, 0x0000, bytes({0, 0}));
    const Datagram reserved_after = line.transact(reserved);
    CHECK(reserved_after.wkc == 0);
    CHECK(reserved_after.address == reserved.address);
    CHECK(reserved_after.data == bytes({0, 0}));
}

TEST_CASE("register writes are shadowed until the frame ends") {
    Line line({drive_description()});
    line.assign_station_addresses();
    Frame frame({physical(Command::Fpwr, 0x1001, 0x0010, le16(0x2222)), physical_read(Command::Fprd, 0x1001, 0x0010, 2),
                 physical_read(Command::Fprd, 0x2222, 0x0010, 2)});
    line.run(frame);
    const auto after = frame.datagrams();
    CHECK(after[0].wkc == 1);
    CHECK(after[1].wkc == 1);
    CHECK(after[1].data == le16(0x1001));  // the old value within the frame
    CHECK(after[2].wkc == 0);              // the new address is not effective yet
    CHECK(line[0].station_address() == 0x2222);

    // RAM has no shadow: a write is visible to the next datagram.
    Frame ram({physical(Command::Fpwr, 0x2222, 0x0F80, bytes({0x5A})), physical_read(Command::Fprd, 0x2222, 0x0F80, 1)});
    line.run(ram);
    CHECK(ram.datagram(1).data == bytes({0x5A}));
}

TEST_CASE("read-only registers keep their value but the write still counts") {
    Line line({drive_description()});
    line.assign_station_addresses();
    CHECK(line.fpwr(0x1001, 0x0000, bytes({0x99, 0x99, 0x99, 0x99})) == 1);
    CHECK(line.fprd(0x1001, 0x0000, 1) == bytes({0x11}));
    CHECK(line.fpwr(0x1001, 0x0012, le16(0x4444)) == 1);  // the alias is read-only for ECAT
    CHECK(line[0].station_alias() == 0);
    CHECK(line.fpwr(0x1001, 0x0130, le16(0x0008)) == 1);  // AL status too
    CHECK(line[0].al_status() == 0x01);
    CHECK(line.fpwr(0x1001, 0x0134, le16(0x0011)) == 1);
    CHECK(line[0].al_status_code() == 0);
}

TEST_CASE("identity registers describe an ET1100-class ESC") {
    auto ebus = drive_description();
    ebus.physics = "KYK";
    Line line({drive_description(), ebus});
    line.assign_station_addresses();
    const auto id = line.fprd(0x1001, 0x0000, 10);
    CHECK(id[0] == 0x11);  // ET1100
    CHECK(id[4] == 8);     // FMMUs
    CHECK(id[5] == 8);     // SyncManagers
    CHECK(id[6] == 8);     // KiB process RAM
    CHECK(id[7] == 0x0F);  // ports 0, 1 MII
    CHECK((id[8] & 0x04) != 0);  // DC supported
    CHECK((id[8] & 0x01) == 0);  // bit-wise FMMU
    CHECK(line.fprd(0x1002, 0x0007, 1) == bytes({0b00'10'11'10}));  // EBUS, MII, EBUS, none
    CHECK(line.fprd(0x1001, 0x0141, 1)[0] == 0x0C);  // device emulation off
}

TEST_CASE("process RAM ends where register 0x0006 says") {
    Line line({drive_description()});
    line.assign_station_addresses();
    CHECK(line.transact(physical(Command::Fpwr, 0x1001, 0x2FFF, bytes({1}))).wkc == 1);
    CHECK(line.transact(physical(Command::Fpwr, 0x1001, 0x3000, bytes({1}))).wkc == 0);
    const Datagram straddling = line.transact(physical(Command::Fprd, 0x1001, 0x2FFE, bytes({7, 7, 7, 7})));
    CHECK(straddling.wkc == 1);
    CHECK(straddling.data == bytes({0, 1, 7, 7}));  // bytes past the RAM are not touched
}

TEST_CASE("every datagram carries the ECAT event request AND mask in its IRQ field") {
    Line line({drive_description(), drive_description()});
    line.assign_station_addresses();
    // Reading DL status clears its event; the mask enables it (as SOEM does).
    line.transact(physical_read(Command::Brd, 0, 0x0110, 2));
    line.transact(physical(Command::Bwr, 0, 0x0200, le16(0x0004)));
    CHECK(line.transact(physical_read(Command::Brd, 0, 0x0000, 1)).irq == 0);

    line[1].set_physical_link(1, true);  // DL status of slave 2 changes
    Datagram nop = physical(Command::Nop, 0, 0, {});
    nop.irq = 0x8000;
    CHECK(line.transact(nop).irq == (0x8000 | 0x0004));
    line.transact(physical_read(Command::Fprd, 0x1002, 0x0110, 2));  // acknowledged
    CHECK(line.transact(physical_read(Command::Brd, 0, 0x0000, 1)).irq == 0);
}
