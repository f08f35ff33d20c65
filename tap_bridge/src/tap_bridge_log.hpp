#pragma once
// The TAP bridge's logger: one name ("tap-bridge") for every file of the module.

#include "ecpair/common/log.hpp"

namespace ecpair::tap_bridge {

inline std::shared_ptr<spdlog::logger> log() { return logger("tap-bridge"); }

}  // namespace ecpair::tap_bridge
