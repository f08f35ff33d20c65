// Fuzz target for the ENI loader: any bytes must either load or give an
// EniError, never crash, hang or read out of bounds. A loaded model is walked
// so that sanitizers see every string and vector the loader built.

#include <cstddef>
#include <cstdint>
#include <string_view>

#include "ecpair/common/log.hpp"
#include "ecpair/eni/loader.hpp"

namespace {

std::size_t touch(const ecpair::eni::EniConfig& config) {
    std::size_t sum = config.root_element.size() + config.master.info.name.size() + config.master.init_cmds.size();
    for (const auto& slave : config.slaves) {
        sum += slave.info.name.size() + slave.info.ring_position + slave.init_cmds.size();
        for (const auto& cmd : slave.init_cmds) sum += cmd.data.size();
        if (slave.mailbox) sum += slave.mailbox->coe_init_cmds.size();
        if (slave.hot_connect) sum += slave.hot_connect->identify_cmds.size();
    }
    for (const auto& cyclic : config.cyclic) {
        for (const auto& frame : cyclic.frames) sum += frame.cmds.size();
    }
    return sum + (config.uses_logical_read_write() ? 1 : 0);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    static const bool quiet = ecpair::set_log_level("off");
    (void)quiet;
    const std::string_view input(reinterpret_cast<const char*>(data), size);
    const auto result = ecpair::eni::load_eni_string(input, "fuzz");
    if (result) {
        volatile std::size_t sink = touch(**result);
        (void)sink;
    } else {
        volatile std::size_t sink = result.error().describe().size();
        (void)sink;
    }
    return 0;
}
