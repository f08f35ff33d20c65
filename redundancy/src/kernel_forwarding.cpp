// KernelForwarding: loads the embedded store-and-forward program (a libbpf
// skeleton generated in the build), attaches it with tcx bpf_links, and
// talks to it through its three maps and its global data, the TAP bridge's
// answers (store_and_forward_maps.h).

#include "ecpair/redundancy/kernel_forwarding.hpp"

#include <net/if.h>
#include <unistd.h>

#include <linux/types.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cstdarg>
#include <cstdio>
#include <cstring>

#include <bpf/bpf.h>
#include <bpf/libbpf.h>
#include <fmt/format.h>

#include "ecpair/common/log.hpp"
// The skeleton names the shared structures: they come first.
#include "store_and_forward_maps.h"
#include "store_and_forward.skel.h"

namespace ecpair::redundancy {
namespace {

// From Linux 6.6's <linux/bpf.h> (Debian 12's headers are older): attach
// types of the tcx hooks, whose attachments are bpf_links.
constexpr auto kTcxIngress = static_cast<bpf_attach_type>(46);

constexpr int kTcActShot = 2;
constexpr int kTcActRedirect = 7;

std::string system_error(int error) { return std::strerror(error); }

// libbpf's own messages (a verifier log, a missing kernel feature) go to our log.
int log_libbpf(libbpf_print_level level, const char* format, va_list args) {
    if (level == LIBBPF_DEBUG) return 0;
    std::array<char, 512> line{};
    std::vsnprintf(line.data(), line.size(), format, args);
    std::string_view text(line.data());
    while (!text.empty() && text.back() == '\n') text.remove_suffix(1);
    logger("redundancy")->debug("libbpf: {}", text);
    return 0;
}

std::string permission_hint(int error) {
    return error == EPERM || error == EACCES ? " (needs CAP_BPF and CAP_NET_ADMIN)" : "";
}

}  // namespace

std::size_t kernel_forwarding_max_pd_in() { return ECPAIR_KFWD_PD_IN_MAX; }

Expected<std::unique_ptr<KernelForwarding>, std::string> KernelForwarding::open(const std::string& main_interface,
                                                                               const std::string& red_interface,
                                                                               std::size_t master_pd_in_size) {
    if (master_pd_in_size > ECPAIR_KFWD_PD_IN_MAX) {
        return unexpected(fmt::format("kernel store-and-forward: master_pd_in_size {} is more than the {} bytes it fills in",
                                      master_pd_in_size, ECPAIR_KFWD_PD_IN_MAX));
    }
    std::array<int, 2> ifindex{};
    const std::array<std::string, 2> names{main_interface, red_interface};
    for (std::size_t i = 0; i < 2; ++i) {
        ifindex[i] = static_cast<int>(if_nametoindex(names[i].c_str()));
        if (ifindex[i] == 0) {
            return unexpected(fmt::format("kernel store-and-forward: no interface {} ({}: {})", names[i],
                                          i == 0 ? "MAIN" : "RED", system_error(errno)));
        }
    }
    libbpf_set_print(log_libbpf);
    auto* skeleton = store_and_forward_bpf__open_and_load();
    if (skeleton == nullptr) {
        const int error = errno;
        return unexpected(fmt::format("kernel store-and-forward: the kernel refused the BPF program: {}{}",
                                      system_error(error), permission_hint(error)));
    }
    return std::unique_ptr<KernelForwarding>(new KernelForwarding(skeleton, names, ifindex, master_pd_in_size));
}

KernelForwarding::KernelForwarding(store_and_forward_bpf* skeleton, std::array<std::string, 2> names,
                                   std::array<int, 2> ifindex, std::size_t master_pd_in_size)
    : skeleton_(skeleton),
      names_(std::move(names)),
      ifindex_(ifindex),
      master_pd_in_size_(master_pd_in_size),
      answer_(sizeof(ecpair_kfwd_answer), 0),
      per_cpu_(static_cast<std::size_t>(std::max(libbpf_num_possible_cpus(), 1)), 0) {
    set_control(ECPAIR_KFWD_IFINDEX_MAIN, static_cast<std::uint32_t>(ifindex_[0]));
    set_control(ECPAIR_KFWD_IFINDEX_RED, static_cast<std::uint32_t>(ifindex_[1]));
    set_control(ECPAIR_KFWD_ANSWER_SLOT, 0);
    set_control(ECPAIR_KFWD_ENABLED, 0);
    // Until the link monitor says otherwise: both up (a frame that cannot leave is lost either way).
    set_control(ECPAIR_KFWD_UP_MAIN, 1);
    set_control(ECPAIR_KFWD_UP_RED, 1);
}

KernelForwarding::~KernelForwarding() {
    detach();
    store_and_forward_bpf__destroy(skeleton_);
}

void KernelForwarding::set_control(std::uint32_t key, std::uint32_t value) const {
    bpf_map_update_elem(bpf_map__fd(skeleton_->maps.control), &key, &value, BPF_ANY);
}

Expected<void, std::string> KernelForwarding::attach() {
    std::lock_guard lock(mutex_);
    const int program = bpf_program__fd(skeleton_->progs.ecpair_store_and_forward);
    for (std::size_t i = 0; i < 2; ++i) {
        if (links_[i] >= 0) continue;
        const int fd = bpf_link_create(program, ifindex_[i], kTcxIngress, nullptr);
        if (fd < 0) {
            const int error = -fd;
            for (auto& link : links_) {
                if (link >= 0) ::close(link);
                link = -1;
            }
            return unexpected(fmt::format(
                "kernel store-and-forward: cannot attach to tc ingress of {}: {}{}", names_[i], system_error(error),
                error == EINVAL ? " (tcx needs Linux 6.6 or newer)" : permission_hint(error)));
        }
        links_[i] = fd;
    }
    logger("redundancy")->info("kernel store-and-forward attached to {} and {} (tcx ingress)", names_[0], names_[1]);
    return {};
}

void KernelForwarding::detach() {
    std::lock_guard lock(mutex_);
    if (links_[0] < 0 && links_[1] < 0) return;
    for (auto& link : links_) {
        if (link >= 0) ::close(link);
        link = -1;
    }
    logger("redundancy")->info("kernel store-and-forward detached from {} and {}", names_[0], names_[1]);
}

bool KernelForwarding::attached() const {
    std::lock_guard lock(mutex_);
    return links_[0] >= 0 && links_[1] >= 0;
}

void KernelForwarding::set_forwarding(bool on) { set_control(ECPAIR_KFWD_ENABLED, on ? 1 : 0); }

void KernelForwarding::set_link_state(master::LinkRole role, bool up) {
    set_control(role == master::LinkRole::Main ? ECPAIR_KFWD_UP_MAIN : ECPAIR_KFWD_UP_RED, up ? 1 : 0);
}

Expected<void, int> KernelForwarding::set_answer(ConstBytes master_pd_in, ConstBytes standby_status) {
    std::lock_guard lock(mutex_);
    auto* answer = reinterpret_cast<ecpair_kfwd_answer*>(answer_.data());
    const std::size_t pd_in = std::min(master_pd_in.size(), master_pd_in_size_);
    answer->pd_in_size = static_cast<std::uint32_t>(master_pd_in_size_);
    std::fill(std::begin(answer->bytes), std::end(answer->bytes), std::uint8_t{0});
    std::copy_n(standby_status.begin(), std::min<std::size_t>(standby_status.size(), ECPAIR_KFWD_STATUS_SIZE),
                std::begin(answer->bytes));
    std::copy_n(master_pd_in.begin(), pd_in, std::begin(answer->bytes) + ECPAIR_KFWD_STATUS_SIZE);
    // Write the slot the program does not read, then point it there.
    const std::uint32_t next = answer_slot_ ^ 1u;
    if (bpf_map_update_elem(bpf_map__fd(skeleton_->maps.answer), &next, answer, BPF_ANY) != 0) {
        return unexpected(errno);  // the caller raises kernel-answer-not-updated (it may repeat every cycle)
    }
    set_control(ECPAIR_KFWD_ANSWER_SLOT, next);
    answer_slot_ = next;
    return {};
}

std::size_t KernelForwarding::slots() const { return ECPAIR_KFWD_BRIDGE_SLOTS; }

// The slots are the program's .bss, mapped into this process: plain memory
// that the program reads as polls pass. Stores that the program must see in
// order (the data before `ready`, `ready` before `bridge_next`) are releases.
std::uint64_t KernelForwarding::claimed_by(std::size_t slot) const {
    auto& answer = skeleton_->bss->bridge_answers[slot % ECPAIR_KFWD_BRIDGE_SLOTS];
    return std::atomic_ref<ecpair_u64>(answer.claimed_by).load(std::memory_order_acquire);
}

void KernelForwarding::publish(std::size_t slot, ConstBytes data) {
    slot %= ECPAIR_KFWD_BRIDGE_SLOTS;
    auto& answer = skeleton_->bss->bridge_answers[slot];
    std::atomic_ref<ecpair_u32>(answer.ready).store(0, std::memory_order_release);
    const std::size_t size = std::min<std::size_t>(data.size(), ECPAIR_KFWD_BRIDGE_DATA_MAX);
    std::copy_n(data.begin(), size, std::begin(answer.data));
    answer.size = static_cast<ecpair_u32>(size);
    std::atomic_ref<ecpair_u64>(answer.claimed_by).store(0, std::memory_order_relaxed);
    std::atomic_ref<ecpair_u32>(answer.ready).store(1, std::memory_order_release);
    std::atomic_ref<ecpair_u32>(skeleton_->bss->bridge_next).store(static_cast<ecpair_u32>(slot),
                                                                    std::memory_order_release);
}

void KernelForwarding::withdraw_all() {
    for (auto& answer : skeleton_->bss->bridge_answers) {
        std::atomic_ref<ecpair_u32>(answer.ready).store(0, std::memory_order_release);
    }
}

StoreAndForwardCounters KernelForwarding::counters() const {
    std::lock_guard lock(counters_mutex_);
    auto sum = [this](std::uint32_t key) {
        std::fill(per_cpu_.begin(), per_cpu_.end(), 0);
        if (bpf_map_lookup_elem(bpf_map__fd(skeleton_->maps.counters), &key, per_cpu_.data()) != 0) return std::uint64_t{0};
        std::uint64_t total = 0;
        for (const auto v : per_cpu_) total += v;
        return total;
    };
    StoreAndForwardCounters c;
    c.forwarded_main_to_red = sum(ECPAIR_KFWD_FORWARDED_MAIN_TO_RED);
    c.forwarded_red_to_main = sum(ECPAIR_KFWD_FORWARDED_RED_TO_MAIN);
    c.bounced = sum(ECPAIR_KFWD_BOUNCED);
    c.dropped_circulating = sum(ECPAIR_KFWD_DROPPED_CIRCULATING);
    c.dropped_non_ethercat = sum(ECPAIR_KFWD_DROPPED_NON_ETHERCAT);
    c.dropped_damaged = sum(ECPAIR_KFWD_DROPPED_DAMAGED);
    return c;
}

Expected<KernelForwardingVerdict, std::string> KernelForwarding::run_once(master::LinkRole arrived_on,
                                                                          ConstBytes frame) const {
    KernelForwardingVerdict verdict;
    verdict.frame.resize(frame.size() + 64);
    __sk_buff context{};
    context.ifindex = static_cast<std::uint32_t>(ifindex_[index(arrived_on)]);
    // Not LIBBPF_OPTS: its designated initialisers of a C struct are a
    // C++ extension that clang's -Wpedantic refuses.
    bpf_test_run_opts run{};
    run.sz = sizeof(run);
    run.data_in = frame.data();
    run.data_size_in = static_cast<std::uint32_t>(frame.size());
    run.data_out = verdict.frame.data();
    run.data_size_out = static_cast<std::uint32_t>(verdict.frame.size());
    run.ctx_in = &context;
    run.ctx_size_in = sizeof(context);
    run.repeat = 1;
    if (bpf_prog_test_run_opts(bpf_program__fd(skeleton_->progs.ecpair_store_and_forward), &run) != 0) {
        return unexpected(fmt::format("BPF_PROG_TEST_RUN: {}", system_error(errno)));
    }
    verdict.frame.resize(run.data_size_out);
    const auto result = static_cast<int>(run.retval);
    verdict.action = result == kTcActRedirect ? KernelForwardingVerdict::Action::Redirected
                     : result == kTcActShot   ? KernelForwardingVerdict::Action::Dropped
                                              : KernelForwardingVerdict::Action::Passed;
    return verdict;
}

}  // namespace ecpair::redundancy
