#pragma once
// What `tc netem` would do to one of ecsim's two cables, for kernels built
// without netem (the failover campaign uses it): lose or duplicate a share of
// the frames crossing the cable in either direction, and delay the frames
// entering the segment by it. Decided per frame with a seeded generator, so
// that a campaign run can be repeated. A "lost" frame is one the cable
// damaged: on its way in, the slave port it reaches counts it (the runner
// carries it as damaged); on its way out, the master's NIC drops it.

#include <chrono>
#include <cstdint>
#include <random>

namespace ecpair::ecsim {

struct Impairment {
    std::uint8_t loss_percent = 0;
    std::uint8_t duplicate_percent = 0;
    std::chrono::microseconds delay{0};
    bool any() const { return loss_percent != 0 || duplicate_percent != 0 || delay.count() != 0; }
};

class CableImpairment {
public:
    explicit CableImpairment(std::uint64_t seed) : random_(seed) {}

    void set(const Impairment& impairment) { impairment_ = impairment; }
    const Impairment& get() const { return impairment_; }
    // How many copies of a frame cross: 0 (damaged), 1, or 2 (duplicated).
    int copies();

    std::uint64_t lost() const { return lost_; }
    std::uint64_t duplicated() const { return duplicated_; }

private:
    Impairment impairment_;
    std::mt19937_64 random_;
    std::uint64_t lost_ = 0;
    std::uint64_t duplicated_ = 0;
};

}  // namespace ecpair::ecsim
