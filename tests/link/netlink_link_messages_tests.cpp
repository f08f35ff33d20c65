// The rtnetlink link-message decoder: what it extracts, the "up" rule, and
// the errors for malformed datagrams (with the offending byte offset).

#include <catch2/catch.hpp>
#include <fstream>
#include <iterator>
#include <map>

#include <fmt/format.h>

#include "netlink_link_messages.hpp"
#include "netlink_message_builder.hpp"

using ecpair::link::detail::decode_netlink_link_messages;
using ecpair::link::detail::encode_link_admin_request;
using ecpair::link::detail::encode_link_dump_request;
using ecpair::link::detail::encode_link_get_request;
using ecpair::link::detail::LinkMessage;
using ecpair::link::test::NetlinkDatagram;

namespace {

constexpr unsigned kUpRunning = IFF_UP | IFF_RUNNING | IFF_LOWER_UP;

LinkMessage decode_single(std::vector<std::uint8_t> bytes) {
    auto batch = decode_netlink_link_messages(bytes);
    REQUIRE(batch);
    REQUIRE(batch->links.size() == 1);
    return batch->links[0];
}

}  // namespace

TEST_CASE("netlink: a new-link message gives index, name, flags, operstate and carrier", "[link][netlink]") {
    const auto link = decode_single(
        NetlinkDatagram().link(RTM_NEWLINK, 7, kUpRunning).name("ecm0").operstate(IF_OPER_UP).carrier(true).bytes());
    CHECK(link.kind == LinkMessage::Kind::New);
    CHECK(link.index == 7);
    CHECK(link.name == "ecm0");
    CHECK(link.flags == kUpRunning);
    CHECK(link.operstate == IF_OPER_UP);
    CHECK(link.carrier == true);
    CHECK(link.is_up());
}

TEST_CASE("netlink: the up rule", "[link][netlink]") {
    auto message = [](std::uint16_t type, unsigned flags) { return NetlinkDatagram().link(type, 1, flags).name("x"); };
    CHECK(decode_single(message(RTM_NEWLINK, kUpRunning).bytes()).is_up());  // no operstate: flags decide
    CHECK(decode_single(message(RTM_NEWLINK, kUpRunning).operstate(IF_OPER_UNKNOWN).bytes()).is_up());
    CHECK_FALSE(decode_single(message(RTM_NEWLINK, IFF_UP).operstate(IF_OPER_LOWERLAYERDOWN).bytes()).is_up());
    CHECK_FALSE(decode_single(message(RTM_NEWLINK, kUpRunning).operstate(IF_OPER_DOWN).bytes()).is_up());
    CHECK_FALSE(decode_single(message(RTM_NEWLINK, IFF_RUNNING).bytes()).is_up());  // administratively down
    CHECK_FALSE(decode_single(message(RTM_NEWLINK, IFF_UP).bytes()).is_up());       // no carrier
    CHECK_FALSE(decode_single(message(RTM_NEWLINK, kUpRunning).carrier(false).bytes()).is_up());
    CHECK(decode_single(message(RTM_NEWLINK, kUpRunning).carrier(true).bytes()).is_up());
    const auto deleted = decode_single(message(RTM_DELLINK, kUpRunning).operstate(IF_OPER_UP).bytes());
    CHECK(deleted.kind == LinkMessage::Kind::Deleted);
    CHECK_FALSE(deleted.is_up());
}

TEST_CASE("netlink: several messages, other types skipped, end of dump", "[link][netlink]") {
    const auto bytes = NetlinkDatagram()
                           .link(RTM_NEWLINK, 1, kUpRunning)
                           .name("lo")
                           .other(RTM_NEWADDR, 24)
                           .link(RTM_NEWLINK, 2, IFF_UP)
                           .name("ecs0")
                           .attribute(IFLA_MTU, "\xdc\x05\x00\x00", 4)
                           .done()
                           .bytes();
    auto batch = decode_netlink_link_messages(bytes);
    REQUIRE(batch);
    REQUIRE(batch->links.size() == 2);
    CHECK(batch->links[0].name == "lo");
    CHECK(batch->links[1].name == "ecs0");
    CHECK(batch->dump_done);
    CHECK(batch->error == 0);
}

TEST_CASE("netlink: an error message carries the kernel's error code", "[link][netlink]") {
    auto batch = decode_netlink_link_messages(NetlinkDatagram().error(-EPERM).bytes());
    REQUIRE(batch);
    CHECK(batch->error == -EPERM);
    CHECK(batch->links.empty());
}

TEST_CASE("netlink: an empty datagram is empty", "[link][netlink]") {
    auto batch = decode_netlink_link_messages({});
    REQUIRE(batch);
    CHECK(batch->links.empty());
    CHECK_FALSE(batch->dump_done);
}

TEST_CASE("netlink: malformed datagrams are errors naming the offset", "[link][netlink]") {
    const auto valid = NetlinkDatagram().link(RTM_NEWLINK, 1, kUpRunning).name("ecm0").bytes();

    SECTION("trailing bytes too few for a header") {
        auto bytes = valid;
        bytes.resize(bytes.size() + 8);
        auto batch = decode_netlink_link_messages(bytes);
        REQUIRE_FALSE(batch);
        CHECK(batch.error().offset == valid.size());
        CHECK(batch.error().problem.find("trailing") != std::string::npos);
    }
    SECTION("message length beyond the datagram") {
        auto bytes = valid;
        bytes.resize(bytes.size() - 4);
        auto batch = decode_netlink_link_messages(bytes);
        REQUIRE_FALSE(batch);
        CHECK(batch.error().offset == 0);
        CHECK(batch.error().problem.find("message length") != std::string::npos);
    }
    SECTION("message length shorter than its header") {
        auto bytes = valid;
        bytes[0] = 8;
        bytes[1] = bytes[2] = bytes[3] = 0;
        REQUIRE_FALSE(decode_netlink_link_messages(bytes));
    }
    SECTION("link payload shorter than ifinfomsg") {
        const auto bytes = NetlinkDatagram().other(RTM_NEWLINK, 8).bytes();
        auto batch = decode_netlink_link_messages(bytes);
        REQUIRE_FALSE(batch);
        CHECK(batch.error().offset == sizeof(nlmsghdr));
        CHECK(batch.error().problem.find("ifinfomsg") != std::string::npos);
    }
    SECTION("attribute length beyond the message") {
        auto bytes = valid;
        const std::size_t attribute_at = sizeof(nlmsghdr) + sizeof(ifinfomsg);
        bytes[attribute_at] = 200;  // rta_len
        auto batch = decode_netlink_link_messages(bytes);
        REQUIRE_FALSE(batch);
        CHECK(batch.error().offset == attribute_at);
        CHECK(batch.error().problem.find("attribute length 200") != std::string::npos);
    }
    SECTION("attribute shorter than its header") {
        auto bytes = valid;
        bytes[sizeof(nlmsghdr) + sizeof(ifinfomsg)] = 2;
        REQUIRE_FALSE(decode_netlink_link_messages(bytes));
    }
    SECTION("empty operstate") {
        const auto bytes = NetlinkDatagram().link(RTM_NEWLINK, 1, 0).attribute(IFLA_OPERSTATE, nullptr, 0).bytes();
        auto batch = decode_netlink_link_messages(bytes);
        REQUIRE_FALSE(batch);
        CHECK(batch.error().problem.find("empty attribute") != std::string::npos);
    }
    SECTION("interface name too long") {
        const auto bytes = NetlinkDatagram().link(RTM_NEWLINK, 1, 0).name(std::string(IFNAMSIZ, 'x')).bytes();
        auto batch = decode_netlink_link_messages(bytes);
        REQUIRE_FALSE(batch);
        CHECK(batch.error().problem.find("too long") != std::string::npos);
    }
    SECTION("error message without a code") {
        const auto bytes = NetlinkDatagram().other(NLMSG_ERROR, 2).bytes();
        REQUIRE_FALSE(decode_netlink_link_messages(bytes));
    }
}

TEST_CASE("netlink: the dump request asks for every link", "[link][netlink]") {
    const auto request = encode_link_dump_request(42);
    nlmsghdr header{};
    std::memcpy(&header, request.data(), sizeof(header));
    CHECK(header.nlmsg_len == request.size());
    CHECK(header.nlmsg_type == RTM_GETLINK);
    CHECK(header.nlmsg_flags == (NLM_F_REQUEST | NLM_F_DUMP));
    CHECK(header.nlmsg_seq == 42);
    ifinfomsg info{};
    std::memcpy(&info, request.data() + sizeof(header), sizeof(info));
    CHECK(info.ifi_family == AF_UNSPEC);
    CHECK(info.ifi_index == 0);
}

TEST_CASE("netlink: the admin request sets or clears IFF_UP of the named interface", "[link][netlink]") {
    for (const bool up : {true, false}) {
        const auto request = encode_link_admin_request(7, "m1-main", up);
        nlmsghdr header{};
        std::memcpy(&header, request.data(), sizeof(header));
        CHECK(header.nlmsg_len == request.size());
        CHECK(request.size() % 4 == 0);
        CHECK(header.nlmsg_type == RTM_NEWLINK);
        CHECK(header.nlmsg_flags == (NLM_F_REQUEST | NLM_F_ACK));
        CHECK(header.nlmsg_seq == 7);
        ifinfomsg info{};
        std::memcpy(&info, request.data() + sizeof(header), sizeof(info));
        CHECK(info.ifi_index == 0);
        CHECK(info.ifi_change == IFF_UP);
        CHECK(info.ifi_flags == (up ? static_cast<unsigned>(IFF_UP) : 0u));
        rtattr attribute{};
        std::memcpy(&attribute, request.data() + sizeof(header) + sizeof(info), sizeof(attribute));
        CHECK(attribute.rta_type == IFLA_IFNAME);
        CHECK(attribute.rta_len == sizeof(rtattr) + 8);  // "m1-main" and its NUL
        const char* name = reinterpret_cast<const char*>(request.data() + sizeof(header) + sizeof(info) + sizeof(attribute));
        CHECK(std::string(name) == "m1-main");
    }
    const auto get = encode_link_get_request(8, "eth0");
    nlmsghdr header{};
    std::memcpy(&header, get.data(), sizeof(header));
    CHECK(header.nlmsg_type == RTM_GETLINK);
    CHECK(header.nlmsg_flags == (NLM_F_REQUEST | NLM_F_ACK));
}

TEST_CASE("netlink: an acknowledgement is an error message with code 0 and the request's sequence", "[link][netlink]") {
    NetlinkDatagram datagram;
    datagram.error(0);
    auto batch = decode_netlink_link_messages(datagram.bytes());
    REQUIRE(batch);
    CHECK(batch->acknowledged);
    CHECK(batch->error == 0);
    auto links = decode_netlink_link_messages(NetlinkDatagram().link(RTM_NEWLINK, 3, IFF_UP).name("ecm0").bytes());
    REQUIRE(links);
    CHECK_FALSE(links->acknowledged);
}

TEST_CASE("netlink: a real kernel dump decodes (seed corpus, veth pair in a namespace)", "[link][netlink]") {
    // kernel_dump_* are the datagrams of one RTM_GETLINK dump in a namespace
    // holding loopback and the veth pair ecm0 (up) / ecs0 (down).
    std::map<std::string, bool> up_by_name;
    bool done = false;
    for (int index = 0;; ++index) {
        std::ifstream in(fmt::format("{}/kernel_dump_{}", LINK_TEST_CORPUS_DIR, index), std::ios::binary);
        if (!in) break;
        const std::vector<std::uint8_t> bytes{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
        auto batch = decode_netlink_link_messages(bytes);
        REQUIRE(batch);
        for (const auto& link : batch->links) up_by_name[link.name] = link.is_up();
        done = done || batch->dump_done;
    }
    CHECK(done);
    REQUIRE(up_by_name.size() == 3);
    CHECK(up_by_name.at("lo") == false);   // never set up there
    CHECK(up_by_name.at("ecm0") == false);  // up, but its peer is down: no carrier
    CHECK(up_by_name.at("ecs0") == false);
}
