// Fuzz target for ecsim's control request parser: any bytes as a request
// line must give a request or an error, never a crash. An accepted request
// must also survive being written back and parsed again unchanged.

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <string_view>

#include "ecpair/sim/control_protocol.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string_view line(reinterpret_cast<const char*>(data), size);
    const auto request = ecpair::sim::parse_control_request(line);
    if (!request) {
        if (request.error().message.empty()) std::abort();
        if (request.error().message.find('\n') != std::string::npos) std::abort();
        return 0;
    }
    std::string again(ecpair::sim::to_string(request->command));
    using ecpair::sim::ControlCommand;
    switch (request->command) {
        case ControlCommand::Status:
        case ControlCommand::Help: break;
        case ControlCommand::SetAlias:
        case ControlCommand::SetId:
            again += " " + std::to_string(request->position) + " " + std::to_string(request->value);
            break;
        case ControlCommand::Impair:
            again += (request->red_side ? " red " : " main ") + std::to_string(request->loss_percent) + " " +
                     std::to_string(request->duplicate_percent) + " " + std::to_string(request->delay_us);
            break;
        case ControlCommand::SetSelector:
            again += " " + std::to_string(request->position) + " " + std::to_string(request->value);
            break;
        case ControlCommand::GroupOff:
        case ControlCommand::GroupOn:
        case ControlCommand::UnplugGroup: again += " " + std::to_string(request->group); break;
        case ControlCommand::PlugGroup:
            again += " " + std::to_string(request->group) + " " + std::to_string(request->at) + " " +
                     std::to_string(request->port);
            break;
        case ControlCommand::PlugUnknown:
            again += " " + std::to_string(request->position) + " " + std::to_string(request->port);
            break;
        case ControlCommand::PlugDuplicate:
            again += " " + std::to_string(request->position) + " " + std::to_string(request->at) + " " +
                     std::to_string(request->port);
            break;
        case ControlCommand::PortErrors:
            again += " " + std::to_string(request->position) + " " + std::to_string(request->port) + " " +
                     std::to_string(request->count);
            break;
        case ControlCommand::RefuseState: {
            static constexpr const char* kStates[] = {"none", "?", "PREOP", "?", "SAFEOP", "?", "?", "?", "OP"};
            again += " " + std::to_string(request->position) + " " + (request->state <= 8 ? kStates[request->state] : "?");
            break;
        }
        default: again += " " + std::to_string(request->position); break;
    }
    const auto reparsed = ecpair::sim::parse_control_request(again);
    if (!reparsed || !(*reparsed == *request)) std::abort();
    return 0;
}
