#include "ecpair/common/log.hpp"

#include <mutex>

#include <spdlog/sinks/stdout_color_sinks.h>

namespace ecpair {
namespace {

std::mutex& registry_mutex() {
    static std::mutex mutex;
    return mutex;
}

spdlog::level::level_enum& default_level() {
    static spdlog::level::level_enum level = spdlog::level::info;
    return level;
}

}  // namespace

std::shared_ptr<spdlog::logger> logger(const std::string& module) {
    std::lock_guard lock(registry_mutex());
    if (auto existing = spdlog::get(module)) return existing;
    auto created = spdlog::stderr_color_mt(module);
    created->set_level(default_level());
    return created;
}

bool set_log_level(const std::string& level_name) {
    const auto level = spdlog::level::from_str(level_name);
    if (level == spdlog::level::off && level_name != "off") return false;
    std::lock_guard lock(registry_mutex());
    default_level() = level;
    spdlog::set_level(level);
    return true;
}

}  // namespace ecpair
