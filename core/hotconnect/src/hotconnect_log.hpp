#pragma once
// The Hot-Connect's logger: one name ("hotconnect") for every file of the module.

#include "ecpair/common/log.hpp"

namespace ecpair::hotconnect {

inline std::shared_ptr<spdlog::logger> log() { return logger("hotconnect"); }

}  // namespace ecpair::hotconnect
