// Writes the seed corpus of fuzz_netlink_link_messages: hand-built datagrams
// covering each message kind the decoder handles, plus the datagrams of a
// real RTM_GETLINK dump from the running kernel. The corpus in
// fuzz_corpus/netlink_link_messages was made in a scratch namespace (so that
// it holds a veth pair and loopback, nothing of the build machine):
//   ip netns add corpus && ip -n corpus link add ecm0 type veth peer name ecs0
//   ip -n corpus link set ecm0 up
//   ip netns exec corpus make_netlink_corpus tests/link/fuzz_corpus/netlink_link_messages
//   ip netns del corpus

#include <linux/netlink.h>
#include <linux/rtnetlink.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "netlink_link_messages.hpp"
#include "netlink_message_builder.hpp"

using ecpair::link::test::NetlinkDatagram;

namespace {

void write_file(const std::filesystem::path& path, const std::vector<std::uint8_t>& bytes) {
    std::ofstream out(path, std::ios::binary);
    out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
}

// The datagrams the kernel sends for one link dump; empty when netlink is unavailable.
std::vector<std::vector<std::uint8_t>> kernel_dump() {
    std::vector<std::vector<std::uint8_t>> datagrams;
    const int socket = ::socket(AF_NETLINK, SOCK_RAW | SOCK_CLOEXEC, NETLINK_ROUTE);
    if (socket < 0) return datagrams;
    const auto request = ecpair::link::detail::encode_link_dump_request(1);
    if (::send(socket, request.data(), request.size(), 0) == static_cast<ssize_t>(request.size())) {
        std::vector<std::uint8_t> buffer(64 * 1024);
        while (true) {
            const ssize_t received = ::recv(socket, buffer.data(), buffer.size(), 0);
            if (received <= 0) break;
            datagrams.emplace_back(buffer.begin(), buffer.begin() + received);
            auto batch = ecpair::link::detail::decode_netlink_link_messages(datagrams.back());
            if (!batch || batch->dump_done) break;
        }
    }
    ::close(socket);
    return datagrams;
}

}  // namespace

int main(int argc, char** argv) {
    if (argc != 2) {
        std::fprintf(stderr, "usage: %s OUTPUT_DIR\n", argv[0]);
        return 2;
    }
    const std::filesystem::path out(argv[1]);
    std::filesystem::create_directories(out);
    constexpr unsigned kUp = IFF_UP | IFF_RUNNING | IFF_LOWER_UP;

    write_file(out / "newlink_up",
               NetlinkDatagram().link(RTM_NEWLINK, 3, kUp).name("ecm0").operstate(IF_OPER_UP).carrier(true).bytes());
    write_file(out / "newlink_lowerlayerdown", NetlinkDatagram()
                                                   .link(RTM_NEWLINK, 4, IFF_UP)
                                                   .name("ecs0")
                                                   .operstate(IF_OPER_LOWERLAYERDOWN)
                                                   .carrier(false)
                                                   .bytes());
    write_file(out / "dellink", NetlinkDatagram().link(RTM_DELLINK, 4, 0).name("ecs0").bytes());
    write_file(out / "dump_tail",
               NetlinkDatagram().link(RTM_NEWLINK, 1, kUp).name("lo").other(RTM_NEWADDR, 24).done().bytes());
    write_file(out / "error", NetlinkDatagram().error(-1).bytes());
    int index = 0;
    for (const auto& datagram : kernel_dump()) write_file(out / ("kernel_dump_" + std::to_string(index++)), datagram);
    std::printf("corpus written to %s (%d kernel datagrams)\n", out.c_str(), index);
    return 0;
}
