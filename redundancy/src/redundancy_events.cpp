// The redundancy's event texts: the role a member changed to, how it took
// over (hot from the mirror, or cold from INIT), what a partner differs in.

#include "ecpair/redundancy/redundancy_events.hpp"

#include <cstring>
#include <utility>

#include <fmt/format.h>

#include "ecpair/redundancy/cmf_writer.hpp"
#include "ecpair/wire/al_status.hpp"

namespace ecpair::redundancy {
namespace {

using master::Event;
using master::EventDescriber;

std::string_view role_text(std::uint32_t state) { return state == 0 ? "INACTIVE" : "ACTIVE"; }

std::string red_state_changed(const Event& e, const EventDescriber&) {
    return fmt::format("redundancy state {} -> {}", role_text(e.a), role_text(e.b));
}

std::string takeover(const Event& e, const EventDescriber&) {
    return e.a != 0 ? fmt::format("hot takeover: now ACTIVE in {}", wire::al_state_name(static_cast<std::uint8_t>(e.b)))
                    : std::string("cold takeover: now ACTIVE, starting from INIT");
}

std::string partner_mismatch(const Event& e, const EventDescriber&) {
    static constexpr std::pair<std::uint32_t, const char*> kNames[] = {
        {kDiffersEni, "ENI"},
        {kDiffersCycleTime, "cycle time"},
        {kDiffersCableRedundancy, "cable redundancy"},
        {kDiffersSplitLrw, "split_lrw"},
        {kDiffersMasterPdOut, "master_pd_out_size"},
        {kDiffersMasterPdIn, "master_pd_in_size"},
        {kDiffersUpdateSlavePdIn, "update_slave_pd_in"},
        {kDiffersUpdateSlavePdOut, "update_slave_pd_out"},
        {kDiffersMaxAcycFrames, "max_acyc_frames_per_cycle"},
        {kDiffersLayout, "the CMF layout (slave count or image sizes)"},
    };
    std::string text;
    for (const auto& [bit, name] : kNames) {
        if ((e.a & bit) == 0) continue;
        if (!text.empty()) text += ", ";
        text += name;
    }
    return "partner differs in: " + (text.empty() ? std::string("something") : text);
}

std::string topology_verified(const Event& e, const EventDescriber&) {
    return fmt::format("background scan {} the mirrored topology", e.a != 0 ? "confirms" : "contradicts");
}

std::string cmf_not_sent(const Event& e, const EventDescriber&) {
    const CmfWriteError error{static_cast<CmfWriteError::What>(e.a), e.b, e.c};
    return fmt::format("no Cyclic Master Red Frame sent: {}; the partner mirrors nothing of this cycle and counts "
                       "towards its comm timeout",
                       error.describe());
}

std::string kernel_answer_not_updated(const Event& e, const EventDescriber&) {
    return fmt::format("the kernel store-and-forward program's answer could not be updated ({}): the CMFs it "
                       "forwards carry this member's previous standby status and master process data",
                       std::strerror(static_cast<int>(e.a)));
}

std::uint64_t first_number(const Event& e) { return e.a; }

}  // namespace

namespace events {

constinit const master::EventType kRedStateChanged{"red-state-changed", red_state_changed};
constinit const master::EventType kTakeover{"takeover", takeover};
constinit const master::EventType kPartnerMismatch{"partner-mismatch", partner_mismatch};
constinit const master::EventType kTopologyVerified{"topology-verified", topology_verified};
constinit const master::EventType kCmfNotSent{"cmf-not-sent", cmf_not_sent, {first_number}};
constinit const master::EventType kKernelAnswerNotUpdated{"kernel-answer-not-updated", kernel_answer_not_updated,
                                                          {first_number}};

}  // namespace events
}  // namespace ecpair::redundancy
