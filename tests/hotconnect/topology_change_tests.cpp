// The topology change state machine: every transition, per mode, and the
// inputs a state ignores.

#include <catch2/catch.hpp>

#include "ecpair/hotconnect/topology_change.hpp"

namespace ecpair::hotconnect {
namespace {

using S = ChangeState;
using I = ChangeInput;
using M = HotConnectMode;

std::optional<S> next(S from, I input, M mode = M::Automatic) { return next_change_state(from, input, mode); }

TEST_CASE("a change in automatic mode: detect, settle, scan, bring up, close", "[hotconnect]") {
    CHECK(next(S::Idle, I::Detected) == S::Settling);
    CHECK(next(S::Settling, I::Settled) == S::Scanning);
    CHECK(next(S::Scanning, I::NewGroups) == S::BringingUp);
    CHECK(next(S::BringingUp, I::BroughtUp) == S::Closing);
    CHECK(next(S::Closing, I::Closed) == S::Idle);
    CHECK(next(S::Scanning, I::NothingNew) == S::Closing);
}

TEST_CASE("the manual modes wait for an accept", "[hotconnect]") {
    CHECK(next(S::Scanning, I::NewGroups, M::ManualPreop) == S::PreparingPreop);
    CHECK(next(S::PreparingPreop, I::BroughtUp, M::ManualPreop) == S::AwaitingAccept);
    CHECK(next(S::Scanning, I::NewGroups, M::ManualNoReset) == S::AwaitingAccept);
    CHECK(next(S::AwaitingAccept, I::Accepted, M::ManualNoReset) == S::BringingUp);
    CHECK(next(S::AwaitingAccept, I::Detected, M::ManualPreop) == S::Settling);  // a new change scans again
}

TEST_CASE("timeouts, failures and cancellation end a change, and what a state cannot use is ignored", "[hotconnect]") {
    CHECK(next(S::Settling, I::Timeout) == S::Idle);
    for (const auto from : {S::Settling, S::Scanning, S::PreparingPreop, S::AwaitingAccept, S::BringingUp, S::Closing}) {
        CHECK(next(from, I::Cancelled) == S::Idle);
        CHECK(next(from, I::ScanFailed) == S::Idle);
    }
    CHECK_FALSE(next(S::Idle, I::Cancelled));
    CHECK_FALSE(next(S::Idle, I::Accepted));
    CHECK_FALSE(next(S::BringingUp, I::Detected));  // handled after the bring-up
    CHECK_FALSE(next(S::Scanning, I::Accepted));
    CHECK_FALSE(next(S::Closing, I::NewGroups));
}

}  // namespace
}  // namespace ecpair::hotconnect
