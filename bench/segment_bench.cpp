// ecsim's processing time per cycle and frame: segments of 33, 128, 256 and
// 512 simulated slaves with 76 bytes in and 76 out each (5 to 78 kB of
// process data, LWR + LRD split over frames plus AL status), brought to OP
// by the real state machine, then the cyclic frames of OP carried through
// the segment over and over. Also the same frames passing the ring
// unprocessed (RED copies).

#include <array>
#include <map>
#include <memory>
#include <vector>

#include <benchmark/benchmark.h>

#include "ecpair/eni/loader.hpp"
#include "ecpair/master/cyclic_exchange.hpp"
#include "ecpair/sequencer/run_without_cyclic_master.hpp"
#include "ecpair/sim/eni_generator.hpp"
#include "ecpair/sim/segment_bus_access.hpp"

namespace {

using namespace ecpair;

struct Frame {
    std::vector<std::uint8_t> bytes;
    std::size_t size;
};

// The segment in OP and the cyclic frames of OP, built once.
struct Fixture {
    explicit Fixture(std::uint32_t slaves) {
        sim::GeneratedEniOptions options;
        options.slaves = slaves;
        eni = eni::load_eni_string(sim::generate_eni(options), "generated.xml").value();
        segment.emplace(sim::Segment::from_eni(*eni).value());
        sim::SegmentBusAccess bus(*segment);
        if (sequencer::run_without_cyclic_master(eni, bus, sequencer::MasterState::Op, std::chrono::seconds(60)) !=
            sequencer::MasterState::Op) {
            throw std::runtime_error("the segment did not reach OP");
        }
        master::CyclicExchange exchange(master::CyclicPlan::build(*eni, {}).value());
        std::vector<std::uint8_t> outputs(exchange.plan().output_image_size, 0x5a);
        wire::EthernetHeader ethernet;
        ethernet.destination = wire::MacAddress::broadcast();
        for (std::size_t i = 0; i < exchange.frame_count(); ++i) {
            Frame f{std::vector<std::uint8_t>(wire::kMaxFrameSizeVlan), 0};
            f.size = exchange.build(i, eni::SlaveState::Op, outputs, ethernet, f.bytes).size();
            frames.push_back(std::move(f));
        }
    }

    std::shared_ptr<const eni::EniConfig> eni;
    std::optional<sim::Segment> segment;
    std::vector<Frame> frames;
};

// One fixture per segment size, built on first use (bringing 512 slaves to OP takes a while).
Fixture& fixture(std::int64_t slaves) {
    static std::map<std::int64_t, std::unique_ptr<Fixture>> fixtures;
    auto& f = fixtures[slaves];
    if (!f) f = std::make_unique<Fixture>(static_cast<std::uint32_t>(slaves));
    return *f;
}

// One iteration carries every cyclic frame of one cycle from MAIN.
void BM_SegmentCycle(benchmark::State& state) {
    auto& fx = fixture(state.range(0));
    std::array<std::uint8_t, wire::kMaxFrameSizeVlan> buffer{};
    std::uint64_t now = 1'000'000'000;
    std::size_t bytes = 0;
    for (auto _ : state) {
        for (const auto& frame : fx.frames) {
            std::copy_n(frame.bytes.begin(), frame.size, buffer.begin());
            std::size_t size = frame.size;
            const auto exit = fx.segment->carry(sim::Side::Main, buffer, size, now += 1000);
            benchmark::DoNotOptimize(exit);
            bytes += size;
        }
    }
    state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(fx.frames.size()));
    state.SetBytesProcessed(static_cast<std::int64_t>(bytes));
    state.counters["frames_per_cycle"] = static_cast<double>(fx.frames.size());
    state.counters["ns_per_frame"] = benchmark::Counter(
        static_cast<double>(state.iterations()) * static_cast<double>(fx.frames.size()),
        benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

// The same frames entering at RED: they pass the slaves unprocessed.
void BM_SegmentUnprocessedPass(benchmark::State& state) {
    auto& fx = fixture(state.range(0));
    std::array<std::uint8_t, wire::kMaxFrameSizeVlan> buffer{};
    std::uint64_t now = 1'000'000'000;
    for (auto _ : state) {
        for (const auto& frame : fx.frames) {
            std::copy_n(frame.bytes.begin(), frame.size, buffer.begin());
            std::size_t size = frame.size;
            benchmark::DoNotOptimize(fx.segment->carry(sim::Side::Red, buffer, size, now += 1000));
        }
    }
    state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(fx.frames.size()));
}

}  // namespace

// Segments of 33, 128, 256 and 512 slaves, 76 + 76 bytes each (5, 19, 38 and 78 kB).
BENCHMARK(BM_SegmentCycle)->Arg(33)->Arg(128)->Arg(256)->Arg(512)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_SegmentUnprocessedPass)->Arg(33)->Arg(128)->Arg(256)->Arg(512)->Unit(benchmark::kMicrosecond);
BENCHMARK_MAIN();
