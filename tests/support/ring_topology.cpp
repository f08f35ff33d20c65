#include "ring_topology.hpp"

#include <stdexcept>

namespace ecpair::test {

RingTopology::RingTopology(Controllers controllers)
    : controllers_(controllers),
      sim_(std::make_unique<TestNamespace>("ecpt-sim")),
      m1_(std::make_unique<TestNamespace>("ecpt-m1")) {
    sim_->create_veth("sim-main", "m1-main");
    sim_->move_link("m1-main", *m1_);
    if (controllers == Controllers::Single) {
        sim_->create_veth("sim-red", "m1-red");
        sim_->move_link("m1-red", *m1_);
        return;
    }
    m2_ = std::make_unique<TestNamespace>("ecpt-m2");
    sim_->create_veth("sim-red", "m2-red");
    sim_->move_link("m2-red", *m2_);
    m1_->create_veth("m1-red", "m2-main");
    m1_->move_link("m2-main", *m2_);
}

void RingTopology::set(Cable cable, bool up) const {
    switch (cable) {
        case Cable::M1Main: m1_->set_link("m1-main", up); return;
        case Cable::RingReturn: sim_->set_link("sim-red", up); return;
        case Cable::MasterMaster:
            if (!m2_) throw std::logic_error("the master-master cable exists only in the pair topology");
            m1_->set_link("m1-red", up);
            return;
    }
}

std::uint64_t RingTopology::frames_dropped_in_cables() const {
    std::uint64_t dropped = sim_->tx_dropped("sim-main") + sim_->tx_dropped("sim-red") +
                            m1_->tx_dropped("m1-main") + m1_->tx_dropped("m1-red");
    if (m2_) dropped += m2_->tx_dropped("m2-main") + m2_->tx_dropped("m2-red");
    return dropped;
}

}  // namespace ecpair::test
