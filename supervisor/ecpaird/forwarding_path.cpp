#include "forwarding_path.hpp"

#include "ecpair/common/log.hpp"

namespace ecpair::daemon {

Expected<std::unique_ptr<redundancy::KernelForwarding>, std::string> open_forwarding_path(
    const config::DaemonSettings& settings) {
    const auto mode = settings.redundancy.forwarding;
    auto log = logger("ecpaird");
    if (mode == config::ForwardingMode::User) {
        log->info("store-and-forward at the INACTIVE: user space (redundancy.forwarding: USER)");
        return std::unique_ptr<redundancy::KernelForwarding>();
    }
    auto opened = redundancy::KernelForwarding::open(settings.main_interface, settings.red_interface,
                                                     settings.redundancy.master_pd_in_size);
    // Attached for ecpaird's life (roles switch it on and off): a NIC or kernel
    // that refuses shows at start-up, and the cycle thread never waits for an attach.
    if (opened) {
        if (auto attached = (*opened)->attach(); !attached) opened = unexpected(attached.error());
    }
    if (!opened) {
        if (mode == config::ForwardingMode::Kernel) return unexpected(opened.error() + " (redundancy.forwarding: KERNEL)");
        log->warn("store-and-forward at the INACTIVE: user space, because {}", opened.error());
        return std::unique_ptr<redundancy::KernelForwarding>();
    }
    log->info("store-and-forward at the INACTIVE: kernel (tcx BPF program on {} and {})", settings.main_interface,
              settings.red_interface);
    return std::move(*opened);
}

}  // namespace ecpair::daemon
