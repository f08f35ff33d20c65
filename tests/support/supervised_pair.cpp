#include "supervised_pair.hpp"

#include <signal.h>

#include <algorithm>
#include <stdexcept>
#include <thread>

namespace ecpair::test {

bool is_active(const control::StatusReply& s) { return s.redundancy().red_state() == "ACTIVE"; }

bool all_slaves_op(const control::StatusReply& s) {
    return s.slaves_size() > 0 && std::all_of(s.slaves().begin(), s.slaves().end(),
                                              [](const auto& slave) { return slave.al_state() == "OP"; });
}

bool hot_standby(const control::StatusReply& s) {
    return s.redundancy().red_state() == "INACTIVE" && s.redundancy().partner_seen() && s.master_state() == "OP";
}

SupervisedPair::SupervisedPair(PairSetup setup, std::string_view prefix)
    : setup_(std::move(setup)), dir_(prefix), topology_(Controllers::Pair) {
    ecsim_.emplace(topology_.sim(), EcsimSettings{setup_.eni, "sim-main", std::string("sim-red"), dir_.path(), 70});
    start(0);
    start(1);
    member(0).wait_ready();
    member(1).wait_ready();
}

void SupervisedPair::start(int i) {
    EcpairdSettings s;
    s.name = name(i);
    s.main_if = s.name + "-main";
    s.red_if = s.name + "-red";
    s.eni = setup_.eni;
    s.dir = dir_.path();
    s.demo = setup_.demo;
    s.wait_until_ready = false;
    // No initial role: the supervisors decide.
    s.extra_config = "cycle_time_us: " + std::to_string(setup_.cycle_us) +
                     "\nredundancy { enabled: true master_pd_out_size: 8 master_pd_in_size: 8 " + setup_.redundancy +
                     " }\n" + setup_.extra_config + "\n";
    members_.at(static_cast<std::size_t>(i)).emplace(ns(i), s);
}

int SupervisedPair::settled(std::chrono::milliseconds timeout) {
    const auto give_up = std::chrono::steady_clock::now() + timeout;
    while (std::chrono::steady_clock::now() < give_up) {
        const auto a = member(0).status();
        const auto b = member(1).status();
        if (is_active(a) && all_slaves_op(a) && hot_standby(b)) return 0;
        if (is_active(b) && all_slaves_op(b) && hot_standby(a)) return 1;
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
    throw std::runtime_error("the pair did not settle with one ACTIVE in OP and a hot standby\nm1:\n" +
                             member(0).log() + "\nm2:\n" + member(1).log());
}

std::uint64_t SupervisedPair::settled_cycle() {
    const int active = settled();
    return member(1 - active).status().redundancy().mirrored_cycle();
}

int SupervisedPair::active_count() {
    int n = 0;
    for (int i = 0; i < 2; ++i) {
        if (member(i).running() && is_active(member(i).status())) ++n;
    }
    return n;
}

void SupervisedPair::restart(int i) {
    members_.at(static_cast<std::size_t>(i)).reset();
    start(i);
    member(i).wait_ready();
}

void SupervisedPair::kill(int i) {
    member(i).signal(SIGKILL);
    const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(5);
    while (member(i).running() && std::chrono::steady_clock::now() < give_up) {
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
}

void SupervisedPair::pull_cables(int i) const {
    ns(i).set_link(name(i) + "-main", false);
    ns(i).set_link(name(i) + "-red", false);
}

void SupervisedPair::plug_cables(int i) const {
    ns(i).set_link(name(i) + "-main", true);
    ns(i).set_link(name(i) + "-red", true);
}

std::size_t SupervisedPair::slaves_leaving_op(std::size_t from) const { return ecsim_->slaves_leaving_op(from); }

std::size_t SupervisedPair::sm_watchdog_expiries(std::size_t from) const { return ecsim_->sm_watchdog_expiries(from); }

SegmentCapture SupervisedPair::capture() {
    if (ecsim_->stop() != 0) throw std::runtime_error("ecsim did not stop cleanly:\n" + ecsim_->log());
    auto read = read_segment_capture(ecsim_->pcap().string());
    if (!read) throw std::runtime_error(read.error());
    return *read;
}

}  // namespace ecpair::test
