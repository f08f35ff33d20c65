// The deviation window in virtual time: a fault told when it starts,
// summarised at most once a second, told when it ends; the recent worst.

#include <catch2/catch.hpp>

#include "ecpair/dc/deviation_monitor.hpp"

using namespace ecpair;
using namespace std::chrono_literals;
using Kind = dc::DeviationReport::Kind;

TEST_CASE("0x092C: sign and magnitude", "[dc]") {
    CHECK(dc::SystemTimeDifference{0x8000'0064u}.signed_ns() == -100);
    CHECK(dc::SystemTimeDifference{0x0000'0064u}.signed_ns() == 100);
    CHECK(dc::SystemTimeDifference::of(-100).raw == 0x8000'0064u);
    CHECK(dc::SystemTimeDifference::of(5'000'000'000).magnitude_ns() == 0x7FFF'FFFFu);
}

TEST_CASE("a deviation out of the window for 9.5 s: one report when it leaves, one a second, one when it is back",
          "[dc]") {
    dc::DeviationMonitor monitor(dc::DeviationMonitorOptions{1000, 1s, 10, 10s});
    std::chrono::steady_clock::time_point now{};
    std::vector<dc::DeviationReport> reports;
    std::uint64_t cycle = 0;
    const auto run = [&](int cycles, std::uint32_t value) {
        for (int i = 0; i < cycles; ++i) {
            now += 1ms;
            if (auto r = monitor.observe(++cycle, now, value)) reports.push_back(*r);
        }
    };
    run(500, 80);
    CHECK(reports.empty());
    CHECK_FALSE(monitor.out_of_window());
    run(9'500, 2500);
    CHECK(monitor.out_of_window());
    REQUIRE(reports.size() == 10);  // left, then a summary each second
    CHECK(reports[0].kind == Kind::Left);
    CHECK(reports[0].worst_ns == 2500);
    CHECK(reports[0].since_cycle == 501);
    for (std::size_t i = 1; i < reports.size(); ++i) {
        CHECK(reports[i].kind == Kind::Summary);
        CHECK(reports[i].cycles_out == 1000);
    }
    run(9, 100);  // not yet settled
    CHECK(reports.size() == 10);
    run(1, 100);
    REQUIRE(reports.size() == 11);
    CHECK(reports.back().kind == Kind::Back);
    CHECK(reports.back().cycles_out == 9'500);
    CHECK(reports.back().worst_ns == 2500);
    CHECK(monitor.recent_worst_ns() == 2500);
    run(25'000, 90);  // two spans later the excursion is forgotten
    CHECK(monitor.recent_worst_ns() == 90);
    CHECK(reports.size() == 11);
}

TEST_CASE("a deviation that flickers around the edge stays one excursion", "[dc]") {
    dc::DeviationMonitor monitor(dc::DeviationMonitorOptions{1000, 1s, 10, 10s});
    std::chrono::steady_clock::time_point now{};
    int reports = 0;
    for (std::uint64_t cycle = 1; cycle <= 3000; ++cycle) {
        now += 1ms;
        if (monitor.observe(cycle, now, cycle % 5 == 0 ? 1200 : 900)) ++reports;
    }
    CHECK(monitor.out_of_window());
    CHECK(reports == 3);  // left, and a summary after each of two seconds
}
