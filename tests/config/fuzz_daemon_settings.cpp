// Fuzz target: any text as an ecpaird configuration.
#include <cstdint>
#include <string>

#include "ecpair/config/daemon_settings.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string text(reinterpret_cast<const char*>(data), size);
    auto settings = ecpair::config::parse_daemon_settings(text, "fuzz");
    if (!settings) (void)settings.error().describe();
    return 0;
}
