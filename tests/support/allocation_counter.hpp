#pragma once
// Counts heap allocations in a test binary: compile allocation_counter.cpp
// into that binary (its SOURCES), and it replaces the global operator new
// and delete. Only for binaries of their own, so that no other test runs
// with the replacement.

#include <cstddef>

namespace ecpair::test {

// Allocations made through operator new since the program started.
std::size_t allocation_count();

// Allocations made by f().
template <class F>
std::size_t allocations_in(F&& f) {
    const std::size_t before = allocation_count();
    f();
    return allocation_count() - before;
}

}  // namespace ecpair::test
