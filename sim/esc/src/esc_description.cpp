// EscDescription::from_eni: what an ENI slave tells about the device.

#include "ecpair/sim/esc.hpp"

namespace ecpair::sim {

namespace {

constexpr std::uint16_t kAliasRegister = 0x0012;
constexpr std::uint16_t kExplicitIdRegister = 0x0134;
constexpr std::uint16_t kProcessRam = 0x1000;

}  // namespace

EscDescription EscDescription::from_eni(const eni::Slave& slave) {
    EscDescription description;
    description.name = slave.info.name;
    description.vendor_id = slave.info.vendor_id;
    description.product_code = slave.info.product_code;
    description.revision_no = slave.info.revision_no;
    description.serial_no = slave.info.serial_no.value_or(0);
    if (!slave.info.physics.empty()) description.physics = slave.info.physics;
    description.mailbox = slave.mailbox;
    description.process_data = slave.process_data;
    if (const auto& identification = slave.info.identification; identification && identification->value) {
        if (identification->ado == kAliasRegister) {
            description.alias = *identification->value;
        } else if (identification->ado == kExplicitIdRegister) {
            description.id_selector = *identification->value;
        } else if (identification->ado >= kProcessRam) {
            description.input_word_id = EscDescription::InputWord{identification->ado, *identification->value};
        }
    }
    return description;
}

}  // namespace ecpair::sim
