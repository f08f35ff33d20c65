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

// Empty: each logger gets its own colour sink on stderr.
std::vector<spdlog::sink_ptr>& installed_sinks() {
    static std::vector<spdlog::sink_ptr> sinks;
    return sinks;
}

}  // namespace

std::shared_ptr<spdlog::logger> logger(const std::string& module) {
    std::lock_guard lock(registry_mutex());
    if (auto existing = spdlog::get(module)) return existing;
    std::shared_ptr<spdlog::logger> created;
    if (installed_sinks().empty()) {
        created = spdlog::stderr_color_mt(module);
    } else {
        created = std::make_shared<spdlog::logger>(module, installed_sinks().begin(), installed_sinks().end());
        spdlog::register_logger(created);
    }
    created->set_level(default_level());
    return created;
}

void set_log_sinks(std::vector<spdlog::sink_ptr> sinks) {
    std::lock_guard lock(registry_mutex());
    installed_sinks() = std::move(sinks);
    spdlog::apply_all([](const std::shared_ptr<spdlog::logger>& existing) { existing->sinks() = installed_sinks(); });
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
