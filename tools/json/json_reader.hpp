#pragma once

#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

#include "status/tool_status.hpp"

// A strict JSON reader (RFC 8259) into a small DOM whose every value knows
// where it was written, so that a caller checking the document's form can
// name the line and column of what it rejects. The project's one JSON module
// (with json_writer.hpp): the tools, the viewer and the benchmarks share it.
// It depends on nothing but the standard library and the tools' status type.
namespace dfm::json {

enum class JsonType { null, boolean, number, string, array, object };

// "null", "a boolean", "a number", "a string", "an array" or "an object".
const char* json_type_phrase(JsonType type);

// A 1-based line and column; columns count characters (UTF-8 code points),
// a tab as one.
struct JsonPosition {
    std::size_t line = 1;
    std::size_t column = 1;
};

// "SOURCE:LINE:COL: ", the start of every located message.
std::string json_location(std::string_view source, JsonPosition at);

// A key or string fit for a message: control characters as \xNN, and at
// most 40 characters, then "...".
std::string json_printable(std::string_view text);

struct JsonMember;

// One value; only the fields of its type mean anything.
struct JsonValue {
    JsonType type = JsonType::null;
    JsonPosition at;  // of its first character
    bool boolean = false;
    double number = 0.0;
    bool integer = false;  // a number written without fraction or exponent
    // A number beyond the range of a double, kept (as ±infinity, its text in
    // `text`) only when JsonOptions::keep_huge_numbers asks for it, so the
    // reader of a schema can name the field.
    bool beyond_double = false;
    std::string text;                 // a string, UTF-8 with escapes resolved (may hold NUL)
    std::vector<JsonValue> items;     // an array's elements
    std::vector<JsonMember> members;  // an object's members in text order, keys unique

    // The member named `key`, or nullptr (also when this is not an object).
    const JsonMember* find(std::string_view key) const;
};

struct JsonMember {
    std::string key;
    JsonPosition at;  // of the key
    JsonValue value;
};

// Arrays and objects nest at most this deep, so no input can exhaust the
// stack of the recursive reader.
inline constexpr std::size_t json_max_depth = 256;

// Parses one JSON text. Strict: no comments, trailing commas, NaN or
// Infinity, leading zeros, unescaped control characters, invalid UTF-8 or
// lone surrogates; a duplicate key is an error, and so is a number beyond
// the range of a double (one too close to zero rounds to zero). A leading
// UTF-8 byte order mark is skipped. `source` names the text in messages:
// "SOURCE:LINE:COL: expected ..., found ..." (DFM_ERROR_PARSE; running out
// of memory is DFM_ERROR_OUT_OF_MEMORY). On failure `out` is null. Never
// throws; safe on any bytes. Thread-safe.
ToolStatus parse_json(std::string_view text, std::string_view source, JsonValue& out);

struct JsonOptions {
    bool keep_huge_numbers = false;  // see JsonValue::beyond_double
};
ToolStatus parse_json(std::string_view text, std::string_view source, const JsonOptions& options,
                      JsonValue& out);

}  // namespace dfm::json
