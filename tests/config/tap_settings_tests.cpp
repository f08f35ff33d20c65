// The tap block of ecpaird's configuration (docs/CONFIG.md): defaults, and
// every refusal naming the field and line, an MTU that does not fit with
// the number that would.

#include <catch2/catch.hpp>

#include "ecpair/config/daemon_settings.hpp"

using ecpair::config::parse_daemon_settings;

namespace {

std::string pair_config(const std::string& tap) {
    return "interfaces { main: \"m1-main\" red: \"m1-red\" }\n"
           "eni_path: \"/etc/ecpair/line.xml\"\n"
           "redundancy { enabled: true }\n" +
           tap + "\n";
}

std::string error_of(const std::string& text) {
    auto r = parse_daemon_settings(text, "m1.textproto");
    REQUIRE_FALSE(r);
    return r.error().describe();
}

}  // namespace

TEST_CASE("no tap block, no bridge; an empty one gets the defaults", "[config][tap_bridge]") {
    auto none = parse_daemon_settings(pair_config(""));
    REQUIRE(none);
    CHECK_FALSE(none->tap.has_value());
    auto s = parse_daemon_settings(pair_config("tap {}"));
    REQUIRE(s);
    REQUIRE(s->tap);
    CHECK(s->tap->name == "ecpair0");
    CHECK(s->tap->addresses.empty());
    CHECK_FALSE(s->tap->mtu);
    CHECK(s->tap->poll_size == 1486);
    CHECK(s->tap->queue_frames == 256);
    // The MAC: the same at every start, another for the partner.
    REQUIRE(s->tap->mac);
    CHECK(*s->tap->mac == ecpair::tap_bridge::default_mac("ecpaird", "ecpair0"));
    CHECK(s->tap->mac->bytes[0] == 0x02);  // locally administered, unicast
    CHECK(ecpair::tap_bridge::default_mac("m1", "ecpair0") != ecpair::tap_bridge::default_mac("m2", "ecpair0"));
}

TEST_CASE("a full tap block", "[config][tap_bridge]") {
    auto s = parse_daemon_settings(pair_config(R"(tap { name: "br0" address: "10.77.0.1/24" address: "fd00:77::1/64"
      mac: "02:00:00:77:00:01" mtu: 1200 poll_size: 1300 queue_frames: 64 })"));
    REQUIRE(s);
    REQUIRE(s->tap);
    CHECK(s->tap->name == "br0");
    REQUIRE(s->tap->addresses.size() == 2);
    CHECK(s->tap->addresses[0].to_string() == "10.77.0.1/24");
    CHECK(s->tap->addresses[1].to_string() == "fd00:77::1/64");
    CHECK(s->tap->mac->to_string() == "02:00:00:77:00:01");
    CHECK(*s->tap->mtu == 1200);
    CHECK(s->tap->poll_size == 1300);
    CHECK(s->tap->queue_frames == 64);
}

TEST_CASE("an MTU that does not fit is refused with the number that would", "[config][tap_bridge]") {
    CHECK(error_of(pair_config("tap {\n  mtu: 1500\n}")) ==
          "m1.textproto:5:3: tap.mtu: tap MTU 1500 does not fit one bridge datagram of one EtherCAT frame: the largest "
          "that fits is 1446 (the smallest allowed is 68)");
    CHECK(error_of(pair_config("tap { mtu: 1447 }")).find("the largest that fits is 1446") != std::string::npos);
    CHECK(parse_daemon_settings(pair_config("tap { mtu: 1446 }")));
    // A smaller poll lowers what fits.
    CHECK(error_of(pair_config("tap { mtu: 1000 poll_size: 1000 }"))
              .find("with a poll of 1000 bytes: the largest that fits is 960") != std::string::npos);
}

TEST_CASE("bad tap settings are refused, naming the field", "[config][tap_bridge]") {
    CHECK(error_of(pair_config("tap { poll_size: 39 }")).find("tap.poll_size: tap poll size 39 is outside 40..1486") !=
          std::string::npos);
    CHECK(error_of(pair_config("tap { address: \"10.77.0.1/33\" }")).find("m1.textproto:4:7: tap.address[0]: '10.77.0.1/33': prefix length") !=
          std::string::npos);
    CHECK(error_of(pair_config("tap { address: \"ten.0.0.1\" }")).find("is no IPv4 or IPv6 address") != std::string::npos);
    CHECK(error_of(pair_config("tap { address: \"10.0.0.1/8\" address: \"10.0.0.2/8\" }")).find("tap.address[1]: '10.0.0.2/8': at most one IPv4") !=
          std::string::npos);
    CHECK(error_of(pair_config("tap { mac: \"01:00:5e:00:00:01\" }")).find("tap.mac:") != std::string::npos);
    CHECK(error_of(pair_config("tap { name: \"a-very-long-tap-name\" }")).find("tap.name:") != std::string::npos);
    CHECK(error_of(pair_config("tap { queue_frames: 0 }")).find("tap.queue_frames: must be 1..4096") != std::string::npos);
    const std::string single = "interfaces { main: \"m1-main\" }\neni_path: \"x.xml\"\ntap {}\n";
    CHECK(error_of(single).find("tap: the TAP bridge rides on the pair's frames: it needs redundancy") != std::string::npos);
}
