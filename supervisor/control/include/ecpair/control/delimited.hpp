#pragma once
// Length-delimited protobuf messages on a byte stream: a varint length, then
// the message bytes (the framing of protobuf's writeDelimitedTo). The reader
// is incremental: feed it whatever the socket gave, take whole messages out.

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

namespace google::protobuf {
class MessageLite;
}

namespace ecpair::control {

inline constexpr std::size_t kMaxMessageSize = 1u << 20;

// The framed bytes of one message.
std::string encode_delimited(const google::protobuf::MessageLite& message);

class DelimitedReader {
public:
    enum class Result : std::uint8_t { NeedMore, Message, Error };

    void feed(std::string_view bytes) { buffer_.append(bytes); }
    // Message: `payload` holds the next message's bytes. Error: `error()` says
    // why (a length over kMaxMessageSize or a malformed varint); the stream
    // cannot be resynchronised after it.
    Result next(std::string& payload);
    const std::string& error() const { return error_; }

private:
    std::string buffer_;
    std::string error_;
};

}  // namespace ecpair::control
