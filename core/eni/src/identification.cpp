#include "ecpair/eni/identification.hpp"

namespace ecpair::eni {

std::string_view to_string(IdentificationMode mode) {
    switch (mode) {
        case IdentificationMode::None: return "none";
        case IdentificationMode::StationAlias: return "station alias";
        case IdentificationMode::ExplicitDeviceId: return "explicit device ID";
        case IdentificationMode::InputWord: return "input word";
        case IdentificationMode::Register: return "register";
    }
    return "?";
}

IdentificationSpec identification_of(const Slave& slave) {
    const auto& id = slave.info.identification;
    if (!id || !id->enabled || !id->value || *id->value == 0) return {};
    IdentificationSpec spec;
    spec.ado = id->ado;
    spec.value = *id->value;
    if (id->ado == kStationAliasRegister) {
        spec.mode = IdentificationMode::StationAlias;
    } else if (id->ado == kExplicitDeviceIdRegister) {
        spec.mode = IdentificationMode::ExplicitDeviceId;
    } else if (id->ado >= kProcessRamStart) {
        spec.mode = IdentificationMode::InputWord;
    } else {
        spec.mode = IdentificationMode::Register;
    }
    return spec;
}

}  // namespace ecpair::eni
