#pragma once
// The FrameSender the RedundancyController gives its AcyclicMasterRedChannel.

#include <cstddef>
#include <cstdint>

#include "ecpair/master/cycle_extension.hpp"

namespace ecpair::redundancy {

// The channel numbers its frames from 0; on the master they carry their own
// index range, and no more than the pair's acyclic frame budget goes out.
class ChannelSender final : public master::FrameSender {
public:
    ChannelSender(master::FrameSender& inner, std::uint16_t base, std::size_t budget)
        : inner_(inner), base_(base), budget_(budget) {}
    Bytes buffer() override { return inner_.buffer(); }
    wire::EthernetHeader ethernet() const override { return inner_.ethernet(); }
    void send(std::uint16_t index, Bytes frame) override {
        if (budget_ == 0) return;
        --budget_;
        inner_.send(static_cast<std::uint16_t>(base_ + index), frame);
    }

private:
    master::FrameSender& inner_;
    std::uint16_t base_;
    std::size_t budget_;
};

}  // namespace ecpair::redundancy
