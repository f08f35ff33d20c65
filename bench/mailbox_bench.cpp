// The SDO upload round trip through the mailbox service: a real Elmo ENI
// (tests/data/eni/ecengineer_rocos_elmo_1slave.xml) on the in-process
// simulated segment, brought to PREOP by the state machine, then
// MailboxService::sdo_upload (future) over and over: an expedited upload
// (0x1018:01, 4 bytes), a normal one (0x1008, the device name) and a
// CompleteAccess one (0x1018, the identity record). Each iteration is the
// whole request: queued, taken by a worker, the mailbox's datagrams
// exchanged with the segment, the future completed. Besides the time it
// prints the datagram exchanges per upload ("exchanges"): on a running
// master each of them waits for one cycle's acyclic frame, so that is the
// round trip in cycles at the ACTIVE.

#include <memory>
#include <stdexcept>

#include <benchmark/benchmark.h>

#include "ecpair/eni/loader.hpp"
#include "ecpair/sequencer/mailbox_service.hpp"
#include "ecpair/sequencer/run_without_cyclic_master.hpp"
#include "ecpair/sequencer/slave_mailboxes.hpp"
#include "ecpair/sim/segment_bus_access.hpp"

namespace {

using namespace ecpair;

// The segment in PREOP and the service over it, built once.
struct Fixture {
    Fixture() {
        auto loaded = eni::load_eni_file(ECPAIR_SOURCE_DIR "/tests/data/eni/ecengineer_rocos_elmo_1slave.xml");
        if (!loaded) throw std::runtime_error(loaded.error().describe());
        eni = std::move(*loaded);
        segment = std::make_unique<sim::Segment>(sim::Segment::from_eni(*eni).value());
        bus = std::make_unique<sim::SegmentBusAccess>(*segment);
        if (sequencer::run_without_cyclic_master(eni, *bus, sequencer::MasterState::Preop, std::chrono::seconds(30)) !=
            sequencer::MasterState::Preop) {
            throw std::runtime_error("the segment did not reach PREOP");
        }
        mailboxes = std::make_unique<sequencer::SlaveMailboxes>(*eni, *bus, sequencer::steady_clock());
        sequencer::MailboxServiceOptions options;
        options.emergency_poll = std::chrono::milliseconds(0);  // no poll thread: only the requests exchange
        service = std::make_unique<sequencer::MailboxService>(eni, *bus, *mailboxes, sequencer::MailboxServiceHooks{},
                                                              sequencer::steady_clock(), options);
    }

    std::shared_ptr<const eni::EniConfig> eni;
    std::unique_ptr<sim::Segment> segment;
    std::unique_ptr<sim::SegmentBusAccess> bus;
    std::unique_ptr<sequencer::SlaveMailboxes> mailboxes;
    std::unique_ptr<sequencer::MailboxService> service;
};

Fixture& fixture() {
    static Fixture f;
    return f;
}

void upload(benchmark::State& state, std::uint16_t index, std::uint8_t subindex, bool complete_access) {
    auto& fx = fixture();
    const std::uint64_t frames_before = fx.bus->frames();
    std::size_t bytes = 0;
    for (auto _ : state) {
        auto result = fx.service->sdo_upload(sequencer::SdoUpload{0, index, subindex, complete_access}).get();
        if (!result) {
            state.SkipWithError(result.error().message.c_str());
            return;
        }
        bytes = result->size();
        benchmark::DoNotOptimize(result);
    }
    state.counters["exchanges"] = benchmark::Counter(static_cast<double>(fx.bus->frames() - frames_before) /
                                                     static_cast<double>(state.iterations()));
    state.counters["bytes"] = static_cast<double>(bytes);
}

void BM_SdoUploadExpedited(benchmark::State& state) { upload(state, 0x1018, 1, false); }
void BM_SdoUploadNormal(benchmark::State& state) { upload(state, 0x1008, 0, false); }
void BM_SdoUploadCompleteAccess(benchmark::State& state) { upload(state, 0x1018, 0, true); }

BENCHMARK(BM_SdoUploadExpedited)->UseRealTime();
BENCHMARK(BM_SdoUploadNormal)->UseRealTime();
BENCHMARK(BM_SdoUploadCompleteAccess)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
