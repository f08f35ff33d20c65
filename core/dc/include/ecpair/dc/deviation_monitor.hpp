#pragma once
// The slaves' distance from the reference clock against a window, cycle by
// cycle: what a BRD of 0x092C (system time difference) returns every cycle.
// Every DC slave ORs its own difference into the BRD's data, so the result's
// magnitude is at least the largest slave's and less than twice it: a window
// check on it never misses a slave out of the window.
//
// Leaving the window is a persistent fault (RULES: told when it starts,
// summarised at most once a second while it lasts, and when it ends): the
// monitor says Left at the first cycle out of the window, Summary at most
// once per `summary_interval` while out (with the worst value and the cycles
// out since the last report), and Back once the deviation has stayed inside
// for `settle_cycles` cycles in a row. It keeps the recent worst (the
// largest of the current and the previous `recent_span`) for operators.
//
// Pure: time is the caller's (virtual in tests).

#include <chrono>
#include <cstdint>
#include <optional>

namespace ecpair::dc {

// Register 0x092C: bit 31 set when the local copy was smaller than the time
// received, bits 30:0 the magnitude in ns.
struct SystemTimeDifference {
    std::uint32_t raw = 0;
    std::uint32_t magnitude_ns() const { return raw & 0x7FFF'FFFFu; }
    bool local_behind() const { return (raw & 0x8000'0000u) != 0; }
    std::int64_t signed_ns() const {
        return local_behind() ? -static_cast<std::int64_t>(magnitude_ns()) : static_cast<std::int64_t>(magnitude_ns());
    }
    static SystemTimeDifference of(std::int64_t ns);  // magnitude saturates at 2^31 - 1
};

struct DeviationMonitorOptions {
    std::uint32_t window_ns = 1000;
    std::chrono::steady_clock::duration summary_interval = std::chrono::seconds(1);
    std::uint32_t settle_cycles = 10;
    std::chrono::steady_clock::duration recent_span = std::chrono::seconds(10);
};

struct DeviationReport {
    enum class Kind : std::uint8_t { Left, Summary, Back };
    Kind kind = Kind::Left;
    std::uint32_t worst_ns = 0;     // Left: the value that left; Summary: the worst since the last report; Back: in all
    std::uint64_t cycles_out = 0;   // Summary: cycles out of the window since the last report; Back: in all
    std::uint64_t since_cycle = 0;  // the cycle it left the window
};

class DeviationMonitor {
public:
    explicit DeviationMonitor(DeviationMonitorOptions options = {});

    // One cycle's deviation (the magnitude of the BRD's 0x092C). A cycle
    // without a reading (its frame was lost) is simply not observed.
    std::optional<DeviationReport> observe(std::uint64_t cycle, std::chrono::steady_clock::time_point now,
                                           std::uint32_t deviation_ns);
    bool out_of_window() const { return out_; }
    std::uint32_t window_ns() const { return options_.window_ns; }
    std::uint32_t last_ns() const { return last_; }
    // The largest deviation of the recent past (the current and the previous span).
    std::uint32_t recent_worst_ns() const;
    void set_window(std::uint32_t window_ns) { options_.window_ns = window_ns; }

private:
    DeviationMonitorOptions options_;
    bool out_ = false;
    std::uint32_t last_ = 0;
    std::uint64_t left_cycle_ = 0;
    std::uint64_t cycles_out_total_ = 0;
    std::uint64_t cycles_out_since_report_ = 0;
    std::uint32_t worst_since_report_ = 0;
    std::uint32_t worst_out_ = 0;
    std::uint32_t inside_in_a_row_ = 0;
    std::chrono::steady_clock::time_point last_report_{};
    std::chrono::steady_clock::time_point span_start_{};
    bool span_started_ = false;
    std::uint32_t worst_this_span_ = 0;
    std::uint32_t worst_previous_span_ = 0;
};

}  // namespace ecpair::dc
