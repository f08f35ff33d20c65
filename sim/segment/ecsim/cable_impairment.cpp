#include "cable_impairment.hpp"

namespace ecpair::ecsim {

int CableImpairment::copies() {
    if (impairment_.loss_percent == 0 && impairment_.duplicate_percent == 0) return 1;
    std::uniform_int_distribution<int> percent(0, 99);
    if (percent(random_) < impairment_.loss_percent) {
        ++lost_;
        return 0;
    }
    if (percent(random_) < impairment_.duplicate_percent) {
        ++duplicated_;
        return 2;
    }
    return 1;
}

}  // namespace ecpair::ecsim
