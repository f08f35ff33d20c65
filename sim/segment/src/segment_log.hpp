#pragma once
// The segment's logger, shared by the files that make up Segment.

#include <spdlog/logger.h>

#include "ecpair/common/log.hpp"

namespace ecpair::sim::detail {

inline spdlog::logger& segment_log() {
    static const auto logger = ecpair::logger("segment");
    return *logger;
}

}  // namespace ecpair::sim::detail
