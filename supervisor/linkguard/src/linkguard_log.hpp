#pragma once
// The link guard's logger: one name ("linkguard") for every file of the module.

#include "ecpair/common/log.hpp"

namespace ecpair::linkguard {

inline std::shared_ptr<spdlog::logger> log() { return logger("linkguard"); }

}  // namespace ecpair::linkguard
