// CoE InitCmds: choose download or upload from Ccs and Data, run it, and
// wrap an SDO failure with the ENI line and comment.

#include "ecpair/sequencer/coe_init_cmd_runner.hpp"

#include <fmt/format.h>

#include "ecpair/common/hex.hpp"
#include "ecpair/common/log.hpp"

namespace ecpair::sequencer {
namespace {

constexpr std::uint8_t kCcsDownload = 1;
constexpr std::uint8_t kCcsUpload = 2;

}  // namespace

std::string CoeInitCmdError::describe() const {
    std::string text = fmt::format("{}, ENI line {}", owner, eni_line);
    if (!comment.empty()) text += fmt::format(" '{}'", comment);
    return text + ": " + sdo.message;
}

Expected<void, CoeInitCmdError> CoeInitCmdRunner::run(SdoClient& sdo, const eni::CoeInitCmd& cmd,
                                                      const std::string& owner, std::stop_token stop) {
    if (cmd.disabled) return {};
    const auto timeout = cmd.timeout.count() > 0 ? cmd.timeout : SdoClient::kDefaultTimeout;
    const auto fail = [&](SdoError error) {
        return unexpected(CoeInitCmdError{owner, cmd.source_line, cmd.comment, std::move(error)});
    };

    const bool upload = cmd.ccs == kCcsUpload && cmd.data.empty();
    if (cmd.ccs == kCcsUpload && !cmd.data.empty() && !upload_with_data_logged_) {
        upload_with_data_logged_ = true;
        logger("sequencer")->info("{}: ENI line {}: CoE InitCmd with Ccs 2 (upload) carries data; executed as a "
                                  "download, as the tool that wrote it means (Advantech dialect)",
                                  owner, cmd.source_line);
    } else if (cmd.ccs != kCcsDownload && cmd.ccs != kCcsUpload) {
        logger("sequencer")->warn("{}: ENI line {}: CoE InitCmd with Ccs {} executed as a download", owner,
                                  cmd.source_line, cmd.ccs);
    }

    if (upload) {
        auto value = sdo.upload(cmd.index, cmd.subindex, cmd.complete_access, timeout, stop);
        if (!value) return fail(std::move(value).error());
        logger("sequencer")->debug("{}: SDO 0x{:04x}:{:02x} = {}", owner, cmd.index, cmd.subindex, to_hex(*value, " "));
        return {};
    }
    auto written = sdo.download(cmd.index, cmd.subindex, cmd.data, cmd.complete_access, timeout, stop);
    if (!written) return fail(std::move(written).error());
    return {};
}

}  // namespace ecpair::sequencer
