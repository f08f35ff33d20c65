#pragma once
// The INACTIVE's hot-standby mirror. The receive threads hand it every frame
// on its first pass through this master (before it went round the ring a
// second time); per arrival link it
//   - feeds the CMF datagrams to that link's assembler (the ACTIVE sends the
//     CMF on MAIN and on RED, so each link sees one full copy in a closed ring),
//   - copies the written data of the cyclic slave frames (LWR, LRW...) into
//     that link's output image, where the cyclic plan puts them.
// On a link, the ACTIVE's cyclic frames of a cycle come before its CMF of
// that cycle, so when a CMF completes, the link's output image belongs to the
// same cycle - if every output datagram the ACTIVE sends in the CMF's master
// state passed on that link since its previous CMF. When one did not (its
// frame was lost on that link, or this master started mirroring between the
// cycle's frames and its CMF), the cycle's outputs are taken from the other
// link's copy, and a cycle whose outputs neither copy brought is not recorded.
// The newest completed cycle is published (briefly locked) for the cycle
// thread, recorded in the image history, and counted complete once both
// copies arrived, or one when the ACTIVE reports a broken ring.
//
// A partner whose fingerprint differs is never mirrored: the difference is
// named once in an event and in mismatch().

#include <array>
#include <atomic>
#include <chrono>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "ecpair/master/cyclic_plan.hpp"
#include "ecpair/master/event_queue.hpp"
#include "ecpair/master/link_role.hpp"
#include "ecpair/master/slave_state_image.hpp"
#include "ecpair/redundancy/cmf_assembler.hpp"
#include "ecpair/redundancy/image_history.hpp"

namespace ecpair::redundancy {

struct MirroredCycle {
    std::uint64_t cycle = 0;
    eni::SlaveState master_state = eni::SlaveState::Init;
    CmfFlags flags;
    std::vector<std::uint8_t> inputs;
    std::vector<std::uint8_t> outputs;
    std::vector<master::SlaveStateEntry> slaves;
    std::vector<std::uint8_t> master_pd_out;
    std::uint8_t copies = 0;  // bit per arrival link that completed this cycle
    bool complete = false;
    // false: no copy so far brought this cycle's outputs; `outputs` are an
    // older cycle's (the newest known), and the cycle is not recorded yet.
    bool outputs_known = false;
};

class Mirror {
public:
    Mirror(const CmfPlan& plan, const master::CyclicPlan& cyclic, std::size_t input_size, std::size_t output_size,
           master::EventQueue& events, ImageHistory& history);

    // ---- receive threads (each link its own thread)
    void on_first_pass(master::LinkRole arrived_on, ConstBytes frame);

    // ---- cycle thread
    // Copies the newest published cycle into `out` when it is newer than
    // `out.cycle` (or is that cycle, now with its outputs); false when there
    // is nothing new.
    bool take_newer(MirroredCycle& out) const;

    // Forgets the published cycle (the next ACTIVE may count cycles from
    // anywhere: a role change) and the output frames the links saw so far.
    void reset();

    // ---- any thread
    std::optional<std::string> mismatch() const;
    // When a CMF last completed (steady clock), or nullopt when none ever did.
    std::optional<std::chrono::steady_clock::time_point> last_completed() const;
    // CMF copies completed so far (either link), counting up.
    std::uint64_t completed() const { return completed_.load(); }
    std::uint64_t errors() const { return errors_.load(); }

private:
    struct OutputSlice {
        wire::Command command;
        std::uint32_t address;
        std::uint16_t length;
        std::uint32_t offset;
        eni::StateSet states;  // the master states the ACTIVE sends it in
    };
    struct PerLink {
        PerLink(const CmfPlan& plan, std::size_t output_size) : assembler(plan), outputs(output_size, 0) {}
        CmfAssembler assembler;
        std::vector<std::uint8_t> outputs;
        std::vector<bool> written;  // per slice: passed since this link's last completed CMF
        std::uint64_t generation = 0;  // the reset() `written` belongs to
    };

    // Whether `link` saw every slice the ACTIVE sends in `state` since its last completed CMF.
    bool wrote_every_slice(const PerLink& link, eni::SlaveState state) const;
    void publish(master::LinkRole link);
    void report_mismatch(master::LinkRole link);

    std::vector<OutputSlice> slices_;
    std::array<PerLink, 2> links_;  // each touched by its link's receive thread only
    std::atomic<std::uint64_t> generation_{0};  // counts reset()s
    master::EventQueue& events_;
    ImageHistory& history_;

    mutable std::mutex mutex_;
    MirroredCycle latest_;
    std::optional<std::chrono::steady_clock::time_point> last_completed_;
    std::optional<std::string> mismatch_;
    std::atomic<std::uint64_t> errors_{0};
    std::atomic<std::uint64_t> completed_{0};
};

}  // namespace ecpair::redundancy
