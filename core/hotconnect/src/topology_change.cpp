#include "ecpair/hotconnect/topology_change.hpp"

namespace ecpair::hotconnect {

std::string_view to_string(HotConnectMode mode) {
    switch (mode) {
        case HotConnectMode::Automatic: return "automatic";
        case HotConnectMode::ManualPreop: return "manual (new groups to PREOP, then an accept)";
        case HotConnectMode::ManualNoReset: return "manual (new groups as they are until an accept)";
    }
    return "?";
}

std::string_view to_string(ChangeState state) {
    switch (state) {
        case ChangeState::Idle: return "idle";
        case ChangeState::Settling: return "settling";
        case ChangeState::Scanning: return "scanning";
        case ChangeState::PreparingPreop: return "preparing PREOP";
        case ChangeState::AwaitingAccept: return "awaiting accept";
        case ChangeState::BringingUp: return "bringing up";
        case ChangeState::Closing: return "closing";
    }
    return "?";
}

std::string_view to_string(ChangeInput input) {
    switch (input) {
        case ChangeInput::Detected: return "change detected";
        case ChangeInput::Settled: return "bus settled";
        case ChangeInput::Timeout: return "detection timeout";
        case ChangeInput::NothingNew: return "no new group";
        case ChangeInput::NewGroups: return "new groups";
        case ChangeInput::BroughtUp: return "bring-up ended";
        case ChangeInput::Accepted: return "accepted";
        case ChangeInput::Closed: return "closed";
        case ChangeInput::ScanFailed: return "scan failed";
        case ChangeInput::Cancelled: return "cancelled";
    }
    return "?";
}

std::optional<ChangeState> next_change_state(ChangeState from, ChangeInput input, HotConnectMode mode) {
    using S = ChangeState;
    using I = ChangeInput;
    if (input == I::Cancelled || input == I::ScanFailed) return from == S::Idle ? std::nullopt : std::optional(S::Idle);
    switch (from) {
        case S::Idle:
            if (input == I::Detected) return S::Settling;
            break;
        case S::Settling:
            if (input == I::Settled) return S::Scanning;
            if (input == I::Timeout) return S::Idle;
            break;
        case S::Scanning:
            if (input == I::NothingNew) return S::Closing;
            if (input == I::NewGroups) {
                switch (mode) {
                    case HotConnectMode::Automatic: return S::BringingUp;
                    case HotConnectMode::ManualPreop: return S::PreparingPreop;
                    case HotConnectMode::ManualNoReset: return S::AwaitingAccept;
                }
            }
            break;
        case S::PreparingPreop:
            if (input == I::BroughtUp) return S::AwaitingAccept;
            break;
        case S::AwaitingAccept:
            if (input == I::Accepted) return S::BringingUp;
            if (input == I::Detected) return S::Settling;
            break;
        case S::BringingUp:
            if (input == I::BroughtUp) return S::Closing;
            break;
        case S::Closing:
            if (input == I::Closed) return S::Idle;
            break;
    }
    return std::nullopt;
}

}  // namespace ecpair::hotconnect
