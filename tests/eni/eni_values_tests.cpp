// The value parsers, the text-encoding step and the model's small helpers.

#include <catch2/catch.hpp>

#include "ecpair/eni/loader.hpp"
#include "text_encoding.hpp"
#include "values.hpp"

namespace ecpair::eni {
namespace {

using namespace detail;

TEST_CASE("numbers: decimal, #x and 0x hex, signs, garbage", "[eni][values]") {
    CHECK(parse_integer("1001") == 1001);
    CHECK(parse_integer("  42\n") == 42);
    CHECK(parse_integer("#x03E9") == 1001);
    CHECK(parse_integer("#x3e9") == 1001);
    CHECK(parse_integer("0x10") == 16);
    CHECK(parse_integer("-1") == -1);
    CHECK(parse_integer("+7") == 7);
    CHECK_FALSE(parse_integer(""));
    CHECK_FALSE(parse_integer("#x"));
    CHECK_FALSE(parse_integer("12a"));
    CHECK_FALSE(parse_integer("1 2"));
    CHECK_FALSE(parse_integer("--1"));
    // Far beyond int64: saturates, so it still fails every range check below.
    CHECK(parse_integer("99999999999999999999999") == std::numeric_limits<std::int64_t>::max());
}

TEST_CASE("numbers are range-checked against their field", "[eni][values]") {
    CHECK(parse_number<std::uint16_t>("65535").value() == 65535);
    CHECK(parse_number<std::uint16_t>("65536").error() == "'65536' is out of range 0..65535");
    CHECK(parse_number<std::uint16_t>("-1").error() == "'-1' is out of range 0..65535");
    CHECK(parse_number<std::uint16_t>("-1", Negative::TwosComplement).value() == 0xFFFF);
    CHECK(parse_number<std::uint16_t>("-32768", Negative::TwosComplement).value() == 0x8000);
    CHECK(parse_number<std::uint16_t>("-32769", Negative::TwosComplement).error() ==
          "'-32769' is out of range -32768..65535");
    CHECK(parse_number<std::uint32_t>("-1", Negative::TwosComplement).value() == 0xFFFFFFFFu);
    CHECK(parse_number<std::uint8_t>("300").error() == "'300' is out of range 0..255");
    CHECK(parse_number<std::int32_t>("-5000").value() == -5000);
    CHECK(parse_number<std::uint32_t>("99999999999999999999999").error().find("out of range") != std::string::npos);
    CHECK(parse_number<std::uint16_t>("abc").error() == "'abc' is not a number (expected decimal or #x hex)");
}

TEST_CASE("long values are shortened in messages", "[eni][values]") {
    const std::string long_text(200, 'z');
    const auto message = parse_number<std::uint16_t>(long_text).error();
    CHECK(message.size() < 100);
    CHECK(message.find("...'") != std::string::npos);
}

TEST_CASE("booleans in every spelling real files use", "[eni][values]") {
    for (const auto* yes : {"1", "true", "True", "TRUE", " true "}) CHECK(parse_boolean(yes).value());
    for (const auto* no : {"0", "false", "False"}) CHECK_FALSE(parse_boolean(no).value());
    CHECK_FALSE(parse_boolean("yes").has_value());
    CHECK_FALSE(parse_boolean("").has_value());
}

TEST_CASE("hexBinary", "[eni][values]") {
    CHECK(parse_hex_binary("e903").value() == std::vector<std::uint8_t>{0xE9, 0x03});
    CHECK(parse_hex_binary("E903").value() == std::vector<std::uint8_t>{0xE9, 0x03});
    CHECK(parse_hex_binary("").value().empty());
    CHECK_THAT(parse_hex_binary("e90").error(), Catch::Contains("odd number of hex digits"));
    CHECK_THAT(parse_hex_binary("0x12").error(), Catch::Contains("only hex digits are allowed"));
}

TEST_CASE("enumerations", "[eni][values]") {
    CHECK(parse_transition("PP").value() == Transition::PP);
    CHECK(parse_transition("ip").value() == Transition::IP);
    CHECK_FALSE(parse_transition("XX").has_value());
    CHECK(parse_state("SAFEOP").value() == SlaveState::Safeop);
    CHECK(parse_state("PreOp").value() == SlaveState::Preop);
    CHECK_FALSE(parse_state("RUN").has_value());
    CHECK(parse_sm_type("MBoxOut").value() == SmType::MailboxOut);
    CHECK(parse_sm_type("MailboxIn").value() == SmType::MailboxIn);
    CHECK(parse_protocol("CoE") == kCoE);
    CHECK_FALSE(parse_protocol("XoE"));
    CHECK(parse_requires("frame").value() == Requires::Frame);
    CHECK(parse_command_code("12").value() == wire::Command::Lrw);
    CHECK(parse_command_code("lrd").value() == wire::Command::Lrd);
    CHECK_THAT(parse_command_code("15").error(), Catch::Contains("not an EtherCAT datagram type"));
}

TEST_CASE("declared encodings", "[eni][encoding]") {
    CHECK(declared_encoding("<?xml version=\"1.0\" encoding=\"iso-8859-1\"?><a/>") == "iso-8859-1");
    CHECK(declared_encoding("<?xml version='1.0' encoding = 'UTF-8' ?><a/>") == "UTF-8");
    CHECK(declared_encoding("\xEF\xBB\xBF<?xml version=\"1.0\" encoding=\"utf-8\"?><a/>") == "utf-8");
    CHECK_FALSE(declared_encoding("<?xml version=\"1.0\"?><a encoding=\"x\"/>"));
    CHECK_FALSE(declared_encoding("<a/>"));
    CHECK_FALSE(declared_encoding("<?xml encoding=\"unterminated"));
}

TEST_CASE("text becomes UTF-8", "[eni][encoding]") {
    const std::string latin1 = "<?xml version=\"1.0\" encoding=\"ISO-8859-1\"?>\n<a>Gr\xF6\xDF" "e</a>";
    const auto converted = to_utf8(latin1).value();
    CHECK(converted.text == "<?xml version=\"1.0\" encoding=\"ISO-8859-1\"?>\n<a>Gr\xC3\xB6\xC3\x9F" "e</a>");
    CHECK_FALSE(converted.reinterpreted_from_line);

    const std::string utf8 = "<?xml version=\"1.0\" encoding=\"utf-8\"?>\n<a>Gr\xC3\xB6\xC3\x9F" "e</a>";
    CHECK(to_utf8(utf8).value().text == utf8);

    // Undeclared and not UTF-8: read as ISO-8859-1, and say where it went wrong.
    const auto guessed = to_utf8("<a>\n\n<b>Gr\xF6\xDF" "e</b></a>").value();
    CHECK(guessed.text == "<a>\n\n<b>Gr\xC3\xB6\xC3\x9F" "e</b></a>");
    CHECK(guessed.reinterpreted_from_line == 3);

    // Overlong forms and surrogates are not UTF-8 either.
    CHECK(to_utf8("<a>\xC0\xAF</a>").value().reinterpreted_from_line == 1);
    CHECK(to_utf8("<a>\xED\xA0\x80</a>").value().reinterpreted_from_line == 1);

    CHECK_THAT(to_utf8("<?xml version=\"1.0\" encoding=\"Shift_JIS\"?><a/>").error(),
               Catch::Contains("'Shift_JIS' is not supported"));
}

TEST_CASE("an undeclared ISO-8859-1 file still yields UTF-8 names", "[eni][encoding]") {
    const std::string xml =
        "<EtherCATConfig><Config><Master><Info><Name>Pr\xFC" "fstand</Name></Info></Master></Config></EtherCATConfig>";
    const auto result = load_eni_string(xml, "undeclared.xml");
    REQUIRE(result.has_value());
    CHECK((*result)->master.info.name == "Pr\xC3\xBC" "fstand");
}

TEST_CASE("model helpers: names and the states a transition connects", "[eni][model]") {
    CHECK(to_string(SlaveState::Safeop) == "SAFEOP");
    CHECK(to_string(Transition::PP) == "PP");
    CHECK(to_string(SmType::MailboxIn) == "MBoxIn");

    struct Case {
        Transition t;
        SlaveState from, to;
    };
    using S = SlaveState;
    const Case cases[] = {
        {Transition::IP, S::Init, S::Preop},  {Transition::PS, S::Preop, S::Safeop}, {Transition::SO, S::Safeop, S::Op},
        {Transition::SP, S::Safeop, S::Preop}, {Transition::OP, S::Op, S::Preop},     {Transition::OS, S::Op, S::Safeop},
        {Transition::PI, S::Preop, S::Init},  {Transition::SI, S::Safeop, S::Init},  {Transition::OI, S::Op, S::Init},
        {Transition::IB, S::Init, S::Boot},   {Transition::BI, S::Boot, S::Init},    {Transition::II, S::Init, S::Init},
        {Transition::PP, S::Preop, S::Preop},
    };
    STATIC_REQUIRE(std::size(cases) == kTransitionCount);
    for (const auto& c : cases) {
        INFO(to_string(c.t));
        CHECK(from_state(c.t) == c.from);
        CHECK(to_state(c.t) == c.to);
        // The code's letters name the two states.
        CHECK(to_string(c.t)[0] == to_string(c.from)[0]);
        CHECK(to_string(c.t)[1] == to_string(c.to)[0]);
    }
}

}  // namespace
}  // namespace ecpair::eni
