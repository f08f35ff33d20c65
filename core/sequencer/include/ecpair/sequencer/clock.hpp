#pragma once
// Time as the sequencer sees it: InitCmd timeouts, Validate polling, SDO
// waits. Polls sleep on this clock (about a millisecond at a time, never
// spinning), and a sleep ends early when the worker is asked to stop. Tests
// inject a virtual clock so that timeouts pass without waiting.

#include <chrono>
#include <stop_token>

namespace ecpair::sequencer {

class Clock {
public:
    using time_point = std::chrono::steady_clock::time_point;
    using duration = std::chrono::steady_clock::duration;

    virtual ~Clock() = default;
    virtual time_point now() = 0;
    // Sleeps `how_long`, or less when `stop` is requested.
    virtual void sleep_for(duration how_long, std::stop_token stop) = 0;
};

// The process's steady clock; sleeps wake up at once on a stop request.
Clock& steady_clock();

// How long a poll loop waits between two reads of a slave register.
inline constexpr std::chrono::milliseconds kPollInterval{1};

}  // namespace ecpair::sequencer
