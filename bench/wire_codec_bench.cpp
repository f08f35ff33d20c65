// Frame encode/decode throughput: building a cyclic-sized frame, parsing it
// and walking its datagrams, the two things every frame costs a master and
// the simulator.

#include <array>

#include <benchmark/benchmark.h>

#include "ecpair/wire/frame.hpp"
#include "ecpair/wire/source_mac.hpp"

namespace {

using namespace ecpair::wire;

// `datagrams` datagrams sharing `payload` data bytes (a typical cyclic frame:
// a few process-data datagrams plus AL status).
ecpair::Bytes build(std::array<std::uint8_t, kMaxFrameSize>& buffer, int datagrams, std::size_t payload) {
    EthernetHeader eth;
    eth.destination = MacAddress::broadcast();
    eth.source = SourceMac{0, false, false, false, false, false, 7, 0, NicBytes{{1, 2, 3}}}.encode();
    FrameBuilder builder(buffer, eth);
    const std::size_t each = payload / static_cast<std::size_t>(datagrams);
    for (int i = 0; i < datagrams; ++i) {
        DatagramHeader h;
        h.command = Command::Lrd;
        h.index = static_cast<std::uint8_t>(i);
        h.address = 0x10000000u + static_cast<std::uint32_t>(i * 0x1000);
        builder.append(h, each);
    }
    return builder.finish();
}

void BM_EncodeFrame(benchmark::State& state) {
    std::array<std::uint8_t, kMaxFrameSize> buffer{};
    const int datagrams = static_cast<int>(state.range(0));
    const auto payload = static_cast<std::size_t>(state.range(1));
    std::size_t bytes = 0;
    for (auto _ : state) {
        auto frame = build(buffer, datagrams, payload);
        benchmark::DoNotOptimize(frame.data());
        bytes += frame.size();
    }
    state.SetBytesProcessed(static_cast<std::int64_t>(bytes));
    state.SetItemsProcessed(state.iterations());
}

void BM_DecodeFrame(benchmark::State& state) {
    std::array<std::uint8_t, kMaxFrameSize> buffer{};
    auto frame = build(buffer, static_cast<int>(state.range(0)), static_cast<std::size_t>(state.range(1)));
    std::size_t bytes = 0;
    for (auto _ : state) {
        auto view = FrameView::parse(frame);
        std::uint32_t wkc = 0;
        for (auto d : *view) wkc += static_cast<std::uint32_t>(d.wkc() + d.header().length);
        benchmark::DoNotOptimize(wkc);
        bytes += frame.size();
    }
    state.SetBytesProcessed(static_cast<std::int64_t>(bytes));
    state.SetItemsProcessed(state.iterations());
}

void BM_SourceMacRoundTrip(benchmark::State& state) {
    SourceMac mac{3, true, false, true, true, false, 0x42, 0, NicBytes{{0xaa, 0xbb, 0xcc}}};
    for (auto _ : state) {
        auto decoded = SourceMac::decode(mac.encode());
        benchmark::DoNotOptimize(decoded);
        ++mac.frame_id;
    }
    state.SetItemsProcessed(state.iterations());
}

}  // namespace

// (datagrams, data bytes): a minimal status frame, a mid-size frame, a full frame.
BENCHMARK(BM_EncodeFrame)->Args({1, 2})->Args({4, 400})->Args({8, 1400});
BENCHMARK(BM_DecodeFrame)->Args({1, 2})->Args({4, 400})->Args({8, 1400});
BENCHMARK(BM_SourceMacRoundTrip);
BENCHMARK_MAIN();
