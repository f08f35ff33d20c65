#include "ecpair/control/delimited.hpp"

#include <fmt/format.h>
#include <google/protobuf/message_lite.h>

namespace ecpair::control {

std::string encode_delimited(const google::protobuf::MessageLite& message) {
    const std::string body = message.SerializeAsString();
    std::string out;
    std::size_t length = body.size();
    do {
        std::uint8_t byte = static_cast<std::uint8_t>(length & 0x7F);
        length >>= 7;
        if (length != 0) byte |= 0x80;
        out.push_back(static_cast<char>(byte));
    } while (length != 0);
    return out + body;
}

DelimitedReader::Result DelimitedReader::next(std::string& payload) {
    std::size_t length = 0;
    std::size_t used = 0;
    for (;;) {
        if (used == buffer_.size()) return Result::NeedMore;
        if (used == 5) {
            error_ = "message length is not a valid varint";
            return Result::Error;
        }
        const auto byte = static_cast<std::uint8_t>(buffer_[used]);
        length |= static_cast<std::size_t>(byte & 0x7F) << (7 * used);
        ++used;
        if ((byte & 0x80) == 0) break;
    }
    if (length > kMaxMessageSize) {
        error_ = fmt::format("message of {} bytes is larger than the {} bytes allowed", length, kMaxMessageSize);
        return Result::Error;
    }
    if (buffer_.size() < used + length) return Result::NeedMore;
    payload.assign(buffer_, used, length);
    buffer_.erase(0, used + length);
    return Result::Message;
}

}  // namespace ecpair::control
