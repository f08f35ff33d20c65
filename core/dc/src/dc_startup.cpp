// DC start-up and re-measurement (see the header for the steps). Every
// step reads or writes all slaves at once (exchange_all: the master packs
// the datagrams into a few frames), by ring position: the positions are the
// ones the count at the start found, and nothing else moves the slaves
// while the worker holds the bus.

#include "ecpair/dc/dc_startup.hpp"

#include <algorithm>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "ecpair/bus/dl_ports.hpp"
#include "ecpair/common/bytes.hpp"
#include "ecpair/common/log.hpp"
#include "ecpair/dc/propagation_delays.hpp"
#include "ecpair/wire/datagram.hpp"
#include "ecpair/wire/esc_registers.hpp"

namespace ecpair::dc {
namespace {

namespace reg = wire::reg;

constexpr std::uint16_t kFeatureDc = 1u << 2;
constexpr std::uint16_t kFeatureDc64 = 1u << 3;
constexpr std::uint8_t kLoopClosed = 0x03;

std::string at(std::uint16_t position, std::uint16_t station) {
    return station != 0 ? fmt::format("position {} (station {})", position, station)
                        : fmt::format("position {}", position);
}

class Batch {
public:
    Batch(bus::BusAccess& bus, const DcStartupOptions& options) : bus_(bus), options_(options) {}

    std::size_t read(std::uint16_t position, std::uint16_t ado, std::size_t length) {
        auto r = bus::read_request(bus::SlaveAddress::position(position), ado, length);
        return add(std::move(r));
    }
    std::size_t write(std::uint16_t position, std::uint16_t ado, std::vector<std::uint8_t> data) {
        bus::DatagramRequest r;
        r.command = wire::Command::Apwr;
        r.address = wire::DatagramHeader::physical(bus::SlaveAddress::position(position).adp(), ado);
        r.data = std::move(data);
        return add(std::move(r));
    }
    // Runs what was added; an error names the first datagram that failed or
    // that no single slave answered.
    Expected<std::vector<bus::DatagramReply>, std::string> run(const char* what) {
        const auto requests = std::move(requests_);
        requests_.clear();
        const auto replies = bus_.exchange_all(requests);
        std::vector<bus::DatagramReply> out;
        out.reserve(replies.size());
        for (std::size_t i = 0; i < replies.size(); ++i) {
            const auto& r = requests[i];
            const auto position = static_cast<std::uint16_t>(0x10000u - (r.address & 0xFFFFu));
            const auto ado = static_cast<std::uint16_t>(r.address >> 16);
            if (!replies[i]) {
                return unexpected(fmt::format("{}: register 0x{:04x} at position {}: {}", what, ado, position,
                                              replies[i].error().message));
            }
            if (replies[i]->wkc != 1) {
                return unexpected(fmt::format("{}: register 0x{:04x} at position {}: WKC {}, expected 1", what, ado,
                                              position, replies[i]->wkc));
            }
            out.push_back(*replies[i]);
        }
        return out;
    }

private:
    std::size_t add(bus::DatagramRequest r) {
        r.timeout = options_.timeout;
        r.retries = options_.retries;
        requests_.push_back(std::move(r));
        return requests_.size() - 1;
    }

    bus::BusAccess& bus_;
    const DcStartupOptions& options_;
    std::vector<bus::DatagramRequest> requests_;
};

std::vector<std::uint8_t> le_bytes(std::uint64_t value, std::size_t length) {
    std::vector<std::uint8_t> bytes(length);
    for (std::size_t i = 0; i < length; ++i) bytes[i] = static_cast<std::uint8_t>(value >> (8 * i));
    return bytes;
}

}  // namespace

std::uint64_t DcStartupOptions::ns_since_2000(std::chrono::system_clock::time_point t) {
    constexpr std::int64_t kUnixAt2000 = 946'684'800;  // s
    const auto ns = std::chrono::duration_cast<std::chrono::nanoseconds>(t.time_since_epoch()).count();
    return static_cast<std::uint64_t>(ns - kUnixAt2000 * 1'000'000'000);
}

DcStartup::DcStartup(bus::BusAccess& bus, DcHost& host, DcStartupOptions options)
    : bus_(bus), host_(host), options_(std::move(options)) {}

Expected<DcSetup, std::string> DcStartup::run(const DcRequest& request) {
    host_.hold(true);
    DcSetup setup;
    auto measured = measure(setup, request);
    if (!measured) {
        host_.hold(false);
        return unexpected(std::move(measured).error());
    }
    host_.configured(setup);
    host_.hold(false);
    return setup;
}

Expected<void, std::string> DcStartup::measure(DcSetup& setup, const DcRequest& request) {
    auto log = logger("dc");
    Batch batch(bus_, options_);

    // 1. The slaves on the bus.
    bus::DatagramRequest count;
    count.command = wire::Command::Brd;
    count.address = wire::DatagramHeader::physical(0, reg::kType);
    count.data.assign(2, 0);
    count.timeout = options_.timeout;
    count.retries = options_.retries;
    const auto counted = bus_.exchange(count);
    if (!counted) return unexpected("counting the slaves: " + counted.error().message);
    if (counted->wkc == 0) return unexpected(std::string("no slave answers"));
    const std::uint16_t slaves = counted->wkc;
    for (std::uint16_t p = 0; p < slaves; ++p) {
        batch.read(p, reg::kFeatures, 2);
        batch.read(p, reg::kStationAddress, 2);
        batch.read(p, reg::kDlStatus, 2);
    }
    auto found = batch.run("reading the slaves' features");
    if (!found) return unexpected(std::move(found).error());
    std::vector<std::array<bool, kPorts>> open(slaves);
    setup.slaves.resize(slaves);
    for (std::uint16_t p = 0; p < slaves; ++p) {
        auto& s = setup.slaves[p];
        const std::size_t row = 3u * p;
        const auto features = load_le<std::uint16_t>((*found)[row].data, 0);
        s.position = p;
        s.station = load_le<std::uint16_t>((*found)[row + 1].data, 0);
        s.has_dc = (features & kFeatureDc) != 0;
        s.wide = (features & kFeatureDc64) != 0;
        const bus::DlPorts dl{load_le<std::uint16_t>((*found)[row + 2].data, 0)};
        for (int port = 0; port < kPorts; ++port) open[p][static_cast<std::size_t>(port)] = dl.downstream(port);
        if (!s.has_dc) s.why = "no DC unit";
    }

    // 2. The reference clock.
    std::vector<std::string> refused;
    std::optional<std::uint16_t> reference;
    for (const auto station : request.candidates) {
        const auto it = std::find_if(setup.slaves.begin(), setup.slaves.end(),
                                     [station](const SlaveClock& s) { return s.station == station; });
        if (it == setup.slaves.end()) {
            refused.push_back(fmt::format("station {} is not on the bus", station));
        } else if (!it->has_dc) {
            refused.push_back(fmt::format("station {} has no DC unit (register 0x0008 bit 2)", station));
        } else {
            reference = it->position;
            break;
        }
    }
    if (!reference) {
        return unexpected(
            fmt::format("no DC-capable slave for the reference clock: {}",
                        refused.empty() ? std::string("no candidate") : fmt::format("{}", fmt::join(refused, ", "))));
    }
    setup.reference_position = *reference;
    setup.reference_station = setup.slaves[*reference].station;
    if (!refused.empty()) {
        log->warn("DC: reference clock at {}: {}", at(*reference, setup.reference_station), fmt::join(refused, ", "));
    }

    auto tree = tree_from_ports(open);
    if (!tree) return unexpected("the bus's topology (DL status): " + tree.error());

    // 3. The exits closed, 4. the latch, the exits opened again.
    host_.ring_opened(true);
    std::vector<std::uint8_t> exit_loops;
    for (const auto& exit : tree->exits) batch.read(static_cast<std::uint16_t>(exit.position), reg::kDlControlLoop, 1);
    auto loops = batch.run("reading the loop settings of the ring's exits");
    if (!loops) {
        host_.ring_opened(false);
        return unexpected(std::move(loops).error());
    }
    for (std::size_t i = 0; i < tree->exits.size(); ++i) {
        const auto& exit = tree->exits[i];
        exit_loops.push_back((*loops)[i].data[0]);
        const auto shift = static_cast<unsigned>(2 * exit.port);
        const auto closed = static_cast<std::uint8_t>((exit_loops.back() & ~(0x03u << shift)) | (static_cast<unsigned>(kLoopClosed) << shift));
        batch.write(static_cast<std::uint16_t>(exit.position), reg::kDlControlLoop, {closed});
    }
    if (!tree->exits.empty()) {
        // Should the write's frame not come back (the exit leads nowhere that
        // returns it), the loop setting read back says whether it was taken.
        if (auto closing = batch.run("closing the ring's exits"); !closing) {
            for (std::size_t i = 0; i < tree->exits.size(); ++i) {
                batch.read(static_cast<std::uint16_t>(tree->exits[i].position), reg::kDlControlLoop, 1);
            }
            auto check = batch.run("closing the ring's exits");
            const auto port_closed = [&](std::size_t i) {
                const auto loop = static_cast<unsigned>(check->at(i).data[0]);
                return ((loop >> static_cast<unsigned>(2 * tree->exits[i].port)) & 0x03u) == kLoopClosed;
            };
            bool all = check.has_value();
            for (std::size_t i = 0; all && i < tree->exits.size(); ++i) all = port_closed(i);
            if (!all) {
                host_.ring_opened(false);
                return unexpected(std::move(closing).error());
            }
        }
    }
    bus::DatagramRequest latch;
    latch.command = wire::Command::Bwr;
    latch.address = wire::DatagramHeader::physical(0, reg::kDcReceiveTimes);
    latch.data.assign(4, 0);
    latch.timeout = options_.timeout;
    latch.retries = options_.retries;
    const auto latched = bus_.exchange(latch);
    std::vector<std::size_t> times(slaves), processing(slaves), delay_now(slaves), offset_now(slaves);
    for (std::uint16_t p = 0; p < slaves; ++p) {
        if (!setup.slaves[p].has_dc) continue;
        times[p] = batch.read(p, reg::kDcReceiveTimes, 16);
        processing[p] = batch.read(p, reg::kDcReceiveTimeEcu, 8);
        offset_now[p] = batch.read(p, reg::kDcSystemTimeOffset, 8);
        delay_now[p] = batch.read(p, reg::kDcSystemTimeDelay, 4);
    }
    auto latches = latched ? batch.run("reading the receive times")
                           : unexpected("latching the receive times: " + latched.error().message);
    for (std::size_t i = 0; i < tree->exits.size(); ++i) {
        batch.write(static_cast<std::uint16_t>(tree->exits[i].position), reg::kDlControlLoop, {exit_loops[i]});
    }
    auto reopened = batch.run("opening the ring's exits again");
    host_.ring_opened(false);
    if (!latches) return unexpected(std::move(latches).error());
    if (!reopened) return unexpected(std::move(reopened).error());

    // 5. Delays.
    auto nodes = orient(*tree, 0, 0);
    for (std::uint16_t p = 0; p < slaves; ++p) {
        nodes[p].has_dc = setup.slaves[p].has_dc;
        if (!nodes[p].has_dc) continue;
        const auto& t = (*latches)[times[p]].data;
        for (int port = 0; port < kPorts; ++port) {
            nodes[p].port_time[static_cast<std::size_t>(port)] =
                load_le<std::uint32_t>(t, static_cast<std::size_t>(4 * port));
        }
        nodes[p].processing_time = load_le<std::uint64_t>((*latches)[processing[p]].data, 0);
    }
    const auto delays = propagation_delays(nodes, *reference);
    if (!delays) return unexpected("propagation delays: " + delays.error());
    for (std::uint16_t p = 0; p < slaves; ++p) {
        auto& s = setup.slaves[p];
        if (!s.has_dc) continue;
        const auto& d = (*delays)[p];
        if (!d.delay) {
            s.why = d.why;
            log->warn("DC: {}: no delay: {}", at(p, s.station), d.why);
            continue;
        }
        if (*d.delay < 0) {
            s.why = "reached before the reference clock";
            continue;
        }
        s.delay = *d.delay;
        const auto current = load_le<std::uint32_t>((*latches)[delay_now[p]].data, 0);
        if (current != static_cast<std::uint32_t>(*s.delay)) {
            batch.write(p, reg::kDcSystemTimeDelay, le_bytes(static_cast<std::uint64_t>(*s.delay), 4));
        }
    }

    // 6. Offsets.
    const auto local_at_latch = [&](std::uint16_t p) { return nodes[p].processing_time; };
    std::uint64_t reference_offset = load_le<std::uint64_t>((*latches)[offset_now[*reference]].data, 0);
    const auto joins = [&request](std::uint16_t station) {
        return std::find(request.joining.begin(), request.joining.end(), station) != request.joining.end();
    };
    if (request.start_up) reference_offset = options_.wall_clock() - local_at_latch(*reference);
    const std::uint64_t reference_at_latch = local_at_latch(*reference) + reference_offset;
    for (std::uint16_t p = 0; p < slaves; ++p) {
        auto& s = setup.slaves[p];
        if (!s.has_dc) continue;
        const bool give = request.start_up || joins(s.station);
        if (!give || (!s.delay && p != *reference)) {
            s.offset = load_le<std::uint64_t>((*latches)[offset_now[p]].data, 0);
            continue;
        }
        const std::uint64_t offset =
            p == *reference ? reference_offset
                            : reference_at_latch + static_cast<std::uint64_t>(*s.delay) - local_at_latch(p);
        s.offset = offset;
        batch.write(p, reg::kDcSystemTimeOffset, le_bytes(offset, s.wide ? 8 : 4));
    }
    auto written = batch.run("writing delays and offsets");
    if (!written) return unexpected(std::move(written).error());

    // 7. Static drift compensation.
    if (request.static_frames > 0) {
        if (auto burst = host_.static_drift_compensation(*reference, request.static_frames); !burst) {
            return unexpected("static drift compensation: " + burst.error());
        }
        setup.static_frames = request.static_frames;
    }

    // 8. Where the slaves are now, and the reference's 64-bit time.
    std::vector<std::size_t> difference(slaves);
    for (std::uint16_t p = 0; p < slaves; ++p) {
        if (setup.slaves[p].has_dc) difference[p] = batch.read(p, reg::kDcSystemTimeDifference, 4);
    }
    const auto time_index = batch.read(*reference, reg::kDcSystemTime, 8);
    auto after = batch.run("reading the system time differences");
    if (!after) return unexpected(std::move(after).error());
    setup.read_at = options_.now();
    setup.reference_time = load_le<std::uint64_t>((*after)[time_index].data, 0);
    for (std::uint16_t p = 0; p < slaves; ++p) {
        if (setup.slaves[p].has_dc)
            setup.slaves[p].difference = load_le<std::uint32_t>((*after)[difference[p]].data, 0);
    }
    return {};
}

}  // namespace ecpair::dc
