#pragma once
// Which path forwards the INACTIVE's frames (redundancy.forwarding,
// docs/CONFIG.md): loads the kernel store-and-forward program and attaches it
// to both links (switched off until the master is INACTIVE), where the
// configuration wants it.
//
//   USER    nullptr: user space forwards
//   AUTO    the kernel path where it works, else nullptr with a warning naming why
//   KERNEL  the kernel path, or an error naming why it cannot run
//
// The start-up log says which path was chosen.

#include <memory>
#include <string>

#include "ecpair/common/expected.hpp"
#include "ecpair/config/daemon_settings.hpp"
#include "ecpair/redundancy/kernel_forwarding.hpp"

namespace ecpair::daemon {

Expected<std::unique_ptr<redundancy::KernelForwarding>, std::string> open_forwarding_path(
    const config::DaemonSettings& settings);

}  // namespace ecpair::daemon
