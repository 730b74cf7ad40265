#include <doctest/doctest.h>

#include <cmath>
#include <random>
#include <string>
#include <string_view>

#include "json/json_reader.hpp"

using namespace dfm::json;

namespace {

JsonValue parse_ok(std::string_view text) {
    JsonValue v;
    const dfm::ToolStatus s = parse_json(text, "t.json", v);
    INFO(s.message());
    REQUIRE(s.is_ok());
    return v;
}

// The message for `text`, which must fail and leave the output null.
std::string error_of(std::string_view text) {
    JsonValue v;
    v.type = JsonType::array;
    const dfm::ToolStatus s = parse_json(text, "t.json", v);
    REQUIRE_FALSE(s.is_ok());
    CHECK(s.code() == DFM_ERROR_PARSE);
    CHECK(v.type == JsonType::null);
    return s.message();
}

struct Case {
    std::string_view text;
    std::string_view message;
};

void check_errors(std::initializer_list<Case> cases) {
    for (const Case& c : cases) {
        CAPTURE(c.text);
        CHECK(error_of(c.text) == c.message);
    }
}

void check_position(const JsonPosition& at, std::size_t line, std::size_t column) {
    CHECK(at.line == line);
    CHECK(at.column == column);
}

}  // namespace

TEST_CASE("json: values, member order and positions") {
    const JsonValue root = parse_ok(
        "{\n"
        "  \"b\": [1, -2.5, true, false, null],\n"
        "  \"a\": {\"c\": \"x\", \"d\": {}},\n"
        "  \"e\": 1e3, \"f\": []\n"
        "}\n");
    REQUIRE(root.type == JsonType::object);
    check_position(root.at, 1, 1);
    REQUIRE(root.members.size() == 4);
    CHECK(root.members[0].key == "b");
    CHECK(root.members[1].key == "a");
    CHECK(root.members[2].key == "e");
    CHECK(root.members[3].key == "f");
    check_position(root.members[0].at, 2, 3);
    check_position(root.members[2].at, 4, 3);

    const JsonValue& b = root.members[0].value;
    REQUIRE(b.type == JsonType::array);
    check_position(b.at, 2, 8);
    REQUIRE(b.items.size() == 5);
    CHECK(b.items[0].type == JsonType::number);
    CHECK(b.items[0].number == 1.0);
    CHECK(b.items[0].integer);
    check_position(b.items[0].at, 2, 9);
    CHECK(b.items[1].number == -2.5);
    CHECK_FALSE(b.items[1].integer);
    check_position(b.items[1].at, 2, 12);
    CHECK(b.items[2].type == JsonType::boolean);
    CHECK(b.items[2].boolean);
    CHECK(b.items[3].type == JsonType::boolean);
    CHECK_FALSE(b.items[3].boolean);
    CHECK(b.items[4].type == JsonType::null);
    check_position(b.items[4].at, 2, 31);

    REQUIRE(root.find("a") != nullptr);
    const JsonValue& a = root.find("a")->value;
    CHECK(a.type == JsonType::object);
    REQUIRE(a.find("c") != nullptr);
    CHECK(a.find("c")->value.type == JsonType::string);
    CHECK(a.find("c")->value.text == "x");
    check_position(a.find("c")->value.at, 3, 14);
    CHECK(a.find("d")->value.members.empty());
    CHECK(root.find("e")->value.number == 1000.0);
    CHECK_FALSE(root.find("e")->value.integer);
    CHECK(root.find("f")->value.type == JsonType::array);
    CHECK(root.find("f")->value.items.empty());
    CHECK(root.find("z") == nullptr);
    CHECK(b.find("b") == nullptr);
}

TEST_CASE("json: any value may stand at the top, with whitespace around it") {
    CHECK(parse_ok(" \t\r\n 42 \n").number == 42.0);
    CHECK(parse_ok("\"s\"").text == "s");
    CHECK(parse_ok("null").type == JsonType::null);
    CHECK(parse_ok("true").boolean);
}

TEST_CASE("json: escapes and UTF-8 in strings") {
    CHECK(parse_ok(R"("\" \\ \/ \b \f \n \r \t")").text == "\" \\ / \b \f \n \r \t");
    CHECK(parse_ok(R"("\u0041\u00e9\u20AC")").text == "A\xc3\xa9\xe2\x82\xac");
    CHECK(parse_ok(R"("\ud83d\ude00")").text == "\xf0\x9f\x98\x80");
    CHECK(parse_ok(R"("\uDBFF\uDFFF")").text == "\xf4\x8f\xbf\xbf");
    CHECK(parse_ok(R"("a\u0000b")").text == std::string("a\0b", 3));
    CHECK(parse_ok("\"\xc3\xa9\xf0\x9f\x98\x80\x7f\"").text == "\xc3\xa9\xf0\x9f\x98\x80\x7f");
}

TEST_CASE("json: columns count characters, not bytes") {
    const JsonValue v = parse_ok("[\"\xc3\xa9\xe2\x82\xac\", 1]");
    check_position(v.items[1].at, 1, 8);
    CHECK(error_of("[\"\xf0\x9f\x98\x80\", x]") == "t.json:1:7: expected a value, found 'x'");
}

TEST_CASE("json: numbers") {
    const JsonValue v = parse_ok(
        "[0, -0, 10, 1.5, -1.5e-3, 1E+2, 2e-2, 123456789012345678901234567890, "
        "1.7976931348623157e308, 4.9e-324, 1e-400, -1000e-330, 0e999999999999]");
    REQUIRE(v.items.size() == 13);
    CHECK(v.items[0].number == 0.0);
    CHECK(v.items[0].integer);
    CHECK(v.items[1].number == 0.0);
    CHECK(std::signbit(v.items[1].number));
    CHECK(v.items[1].integer);
    CHECK(v.items[2].number == 10.0);
    CHECK(v.items[3].number == 1.5);
    CHECK(v.items[4].number == -1.5e-3);
    CHECK(v.items[5].number == 100.0);
    CHECK_FALSE(v.items[5].integer);
    CHECK(v.items[6].number == 0.02);
    CHECK(v.items[7].number == doctest::Approx(1.2345678901234568e29));
    CHECK(v.items[7].integer);
    CHECK(v.items[8].number == 1.7976931348623157e308);
    CHECK(v.items[9].number > 0.0);
    // Too close to zero rounds to zero, keeping the sign.
    CHECK(v.items[10].number == 0.0);
    CHECK(v.items[11].number == 0.0);
    CHECK(std::signbit(v.items[11].number));
    CHECK(v.items[12].number == 0.0);
}

TEST_CASE("json: malformed numbers") {
    check_errors({
        {"01", "t.json:1:1: a number cannot start with a leading zero"},
        {"[-007]", "t.json:1:2: a number cannot start with a leading zero"},
        {"-", "t.json:1:2: expected a digit after '-', found the end of the text"},
        {"1.", "t.json:1:3: expected a digit after the decimal point, found the end of the text"},
        {"1.e5", "t.json:1:3: expected a digit after the decimal point, found 'e5'"},
        {".5", "t.json:1:1: expected a value, found '.5'"},
        {"+1", "t.json:1:1: expected a value, found '+1'"},
        {"1e", "t.json:1:3: expected a digit in the exponent, found the end of the text"},
        {"1e+", "t.json:1:4: expected a digit in the exponent, found the end of the text"},
        {"NaN", "t.json:1:1: expected a value, found 'NaN'"},
        {"Infinity", "t.json:1:1: expected a value, found 'Infinity'"},
        {"-Infinity", "t.json:1:2: expected a digit after '-', found 'Infinity'"},
        {"0x10", "t.json:1:2: expected the end of the text after the top-level value, found 'x10'"},
        {"1e999", "t.json:1:1: the number 1e999 is beyond the range of a double"},
        {"[1, -1.8e308]", "t.json:1:5: the number -1.8e308 is beyond the range of a double"},
        {"0.01e311", "t.json:1:1: the number 0.01e311 is beyond the range of a double"},
    });
}

TEST_CASE("json: literals are whole lower-case words") {
    check_errors({
        {"tru", "t.json:1:1: expected a value, found 'tru'"},
        {"True", "t.json:1:1: expected a value, found 'True'"},
        {"nul", "t.json:1:1: expected a value, found 'nul'"},
        {"[truex]", "t.json:1:2: expected a value, found 'truex'"},
        {"'a'", "t.json:1:1: expected a value, found '''"},
        {"// note\n1", "t.json:1:1: expected a value, found '/'"},
    });
}

TEST_CASE("json: malformed strings") {
    check_errors({
        {"\"abc",
         "t.json:1:5: expected '\"' to end the string started at 1:1, found the end of the text"},
        {"[\"ab\ncd\"]",
         "t.json:1:5: expected '\"' to end the string started at 1:2, found a line break"},
        {"\"a\tb\"",
         "t.json:1:3: a control character (\\x09) must be written as an escape in a string"},
        {R"("\x")",
         "t.json:1:2: expected an escape after '\\' (one of \" \\ / b f n r t u), found 'x'"},
        {"\"\\",
         "t.json:1:2: expected an escape after '\\' (one of \" \\ / b f n r t u), found the end of "
         "the text"},
        {R"("\u12G4")", "t.json:1:6: expected four hex digits after '\\u', found 'G4'"},
        {R"("\u12")", "t.json:1:6: expected four hex digits after '\\u', found '\"'"},
        {R"("\ud83d")",
         "t.json:1:2: the high surrogate \\ud83d must be followed by a low surrogate (\\uDC00 to "
         "\\uDFFF)"},
        {R"("\ud83dx")",
         "t.json:1:2: the high surrogate \\ud83d must be followed by a low surrogate (\\uDC00 to "
         "\\uDFFF)"},
        {R"("\ud83d\u0041")",
         "t.json:1:8: the high surrogate \\ud83d must be followed by a low surrogate (\\uDC00 to "
         "\\uDFFF)"},
        {R"("\ude00")",
         "t.json:1:2: the low surrogate \\ude00 must follow a high surrogate (\\uD800 to \\uDBFF)"},
        {"\"\xff\"", "t.json:1:2: invalid UTF-8 in a string at byte \\xff"},
        {"\"\x80\"", "t.json:1:2: invalid UTF-8 in a string at byte \\x80"},
        {"\"\xc0\x80\"", "t.json:1:2: invalid UTF-8 in a string at byte \\xc0"},
        {"\"\xe0\x80\xaf\"", "t.json:1:2: invalid UTF-8 in a string at byte \\xe0"},
        {"\"\xed\xa0\x80\"", "t.json:1:2: invalid UTF-8 in a string at byte \\xed"},
        {"\"\xf4\x90\x80\x80\"", "t.json:1:2: invalid UTF-8 in a string at byte \\xf4"},
        {"\"a\xe2\x82\"", "t.json:1:3: invalid UTF-8 in a string at byte \\xe2"},
        {"\"\xe2\x82", "t.json:1:2: invalid UTF-8 in a string at byte \\xe2"},
        {"\xc3\xa9", "t.json:1:1: expected a value, found the byte \\xc3"},
    });
}

TEST_CASE("json: malformed structure") {
    check_errors({
        {"", "t.json:1:1: expected a value, found the end of the text"},
        {" \n  ", "t.json:2:3: expected a value, found the end of the text"},
        {"{\"a\": [1, 2",
         "t.json:1:12: expected ',' or ']' after an array element, found the end of the text"},
        {"{\"a\": 1",
         "t.json:1:8: expected ',' or '}' after an object member, found the end of the text"},
        {"{\"a\":", "t.json:1:6: expected a value, found the end of the text"},
        {"{\"a\"", "t.json:1:5: expected ':' after an object key, found the end of the text"},
        {"[", "t.json:1:2: expected a value, found the end of the text"},
        {"{} x", "t.json:1:4: expected the end of the text after the top-level value, found 'x'"},
        {"1 2", "t.json:1:3: expected the end of the text after the top-level value, found '2'"},
        {"[1]]", "t.json:1:4: expected the end of the text after the top-level value, found ']'"},
        {"[1,]", "t.json:1:4: expected a value, found ']'"},
        {"[,1]", "t.json:1:2: expected a value, found ','"},
        {"[1 2]", "t.json:1:4: expected ',' or ']' after an array element, found '2'"},
        {"{\"a\":1,}", "t.json:1:8: expected a string key after ',', found '}'"},
        {"{a:1}", "t.json:1:2: expected a string key or '}', found 'a'"},
        {"{\"a\" 1}", "t.json:1:6: expected ':' after an object key, found '1'"},
        {"{\"a\":1 \"b\":2}", "t.json:1:8: expected ',' or '}' after an object member, found '\"'"},
        {"{\n \"a\": 1,\n \"b\": {\"a\": 2},\n \"a\": 3\n}",
         "t.json:4:2: duplicate key \"a\" (first at 2:2)"},
        {R"({"\u0061": 1, "a": 2})", "t.json:1:15: duplicate key \"a\" (first at 1:2)"},
        {std::string_view("[1,\0]", 5), "t.json:1:4: expected a value, found the byte \\x00"},
    });
}

TEST_CASE("json: nesting is limited, so deep input cannot exhaust the stack") {
    const std::string deepest = std::string(json_max_depth, '[') + std::string(json_max_depth, ']');
    CHECK(parse_ok(deepest).type == JsonType::array);
    const std::string too_deep = "[" + deepest + "]";
    CHECK(error_of(too_deep) == "t.json:1:257: arrays and objects nest deeper than 256 levels");
    CHECK(error_of(std::string(100000, '[')) ==
          "t.json:1:257: arrays and objects nest deeper than 256 levels");
    std::string objects;
    for (int i = 0; i < 100000; ++i) objects += "{\"a\":";
    CHECK(error_of(objects) == "t.json:1:1281: arrays and objects nest deeper than 256 levels");
}

TEST_CASE("json: CRLF line ends and a byte order mark") {
    const JsonValue v = parse_ok("\xef\xbb\xbf{\r\n \"a\": 1}");
    check_position(v.at, 1, 1);
    check_position(v.members[0].at, 2, 2);
    CHECK(error_of("\xef\xbb\xbf[\r\n x]") == "t.json:2:2: expected a value, found 'x'");
    CHECK(error_of("\xef\xbb\xbf\xef\xbb\xbf"
                   "1") == "t.json:1:1: expected a value, found the byte \\xef");
}

TEST_CASE("json: printable text for messages") {
    CHECK(json_printable("plain") == "plain");
    CHECK(json_printable(std::string_view("a\0b\n\x7f", 5)) == "a\\x00b\\x0a\\x7f");
    CHECK(json_printable(std::string(50, 'k')) == std::string(40, 'k') + "...");
    // Cut between characters, never inside one.
    std::string wide;
    for (int i = 0; i < 41; ++i) wide += "\xc3\xa9";
    CHECK(json_printable(wide) == wide.substr(0, 80) + "...");
    CHECK(json_location("a.json", {3, 14}) == "a.json:3:14: ");
    CHECK(std::string(json_type_phrase(JsonType::object)) == "an object");
}

TEST_CASE("json: damaged and random bytes give a located error or a value, never a crash") {
    const std::string valid =
        R"({"mesh": "model:cow", "roi": {"water_fill": {"first": 1, "last": 2}},
 "handles": [{"vertices": [1, 2e-3, -0.5], "rotate": {"axis": [0, 0, 1], "degrees": 30,
 "pivot": "centr\u00f6id \ud83d\ude00"}}], "x": [true, false, null, {}, []]})";
    std::mt19937 rng(20240611u);
    for (int trial = 0; trial < 20000; ++trial) {
        std::string text = valid;
        const int edits = 1 + static_cast<int>(rng() % 4);
        for (int e = 0; e < edits && !text.empty(); ++e) {
            const std::size_t at = rng() % text.size();
            switch (rng() % 4) {
                case 0: text[at] = static_cast<char>(rng() % 256); break;
                case 1: text.erase(at, 1 + rng() % 8); break;
                case 2: text.insert(at, 1, "{}[]\",:\\0-eE.u"[rng() % 14]); break;
                default: text.resize(at); break;
            }
        }
        if (trial % 10 == 0) {
            text.resize(rng() % 64);
            for (char& c : text) c = static_cast<char>(rng() % 256);
        }
        JsonValue v;
        const dfm::ToolStatus s = parse_json(text, "t.json", v);
        if (!s) {
            CAPTURE(text);
            REQUIRE(s.message().starts_with("t.json:"));
            REQUIRE(v.type == JsonType::null);
        }
    }
}
