#pragma once
// Executes the ENI's CoE InitCmds (Mailbox/CoE/InitCmds) through an
// SdoClient:
//   Ccs 1            download of Data (CompleteAccess as the ENI says);
//   Ccs 2, no Data   upload (the value is logged, nothing else is done);
//   Ccs 2 with Data  Advantech's dialect: the tool writes the upload code but
//                    means a write, so it is executed as a download. Logged
//                    once per runner (docs/STATE_MACHINE.md).
// Disabled commands (EAS) are skipped. Timeout 0 means SdoClient's default.

#include <stop_token>
#include <string>

#include "ecpair/common/expected.hpp"
#include "ecpair/eni/model.hpp"
#include "ecpair/sequencer/sdo_client.hpp"

namespace ecpair::sequencer {

struct CoeInitCmdError {
    std::string owner;  // "slave 'X' (station 1001)"
    int eni_line = 0;
    std::string comment;
    SdoError sdo;

    std::string describe() const;
};

class CoeInitCmdRunner {
public:
    Expected<void, CoeInitCmdError> run(SdoClient& sdo, const eni::CoeInitCmd& cmd, const std::string& owner,
                                        std::stop_token stop = {});

private:
    bool upload_with_data_logged_ = false;
};

}  // namespace ecpair::sequencer
