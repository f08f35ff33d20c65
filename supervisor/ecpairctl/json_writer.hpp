#pragma once
// A tiny JSON writer for ecpairctl's --json output: objects, arrays,
// strings (escaped; bytes that are not UTF-8 become U+FFFD), integers,
// doubles (not finite: null), booleans, null. Commas and nesting are kept
// by the writer; a key is written before every value inside an object.
//
//   JsonWriter w;
//   w.begin_object().key("red_state").value("ACTIVE").key("cycles").value(std::uint64_t{12}).end_object();
//   w.str() == R"({"red_state":"ACTIVE","cycles":12})"

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace ecpair::ctl {

class JsonWriter {
public:
    JsonWriter& begin_object();
    JsonWriter& end_object();
    JsonWriter& begin_array();
    JsonWriter& end_array();
    JsonWriter& key(std::string_view name);
    JsonWriter& value(std::string_view text);
    JsonWriter& value(const char* text) { return value(std::string_view(text)); }
    JsonWriter& value(bool b);
    JsonWriter& value(std::int64_t n);
    JsonWriter& value(std::uint64_t n);
    JsonWriter& value(std::uint32_t n) { return value(std::uint64_t{n}); }
    JsonWriter& value(std::int32_t n) { return value(std::int64_t{n}); }
    JsonWriter& value(double d);
    JsonWriter& null();

    const std::string& str() const { return text_; }

private:
    void before_value();
    void string(std::string_view text);

    std::string text_;
    std::vector<bool> first_;  // per open container: nothing written in it yet
    bool after_key_ = false;
};

}  // namespace ecpair::ctl
