#include "json/json_reader.hpp"

#include <charconv>
#include <cstdint>
#include <limits>
#include <new>
#include <unordered_set>
#include <utility>

namespace dfm::json {

namespace {

constexpr char hex_digits[] = "0123456789abcdef";

void append_hex_byte(std::string& out, unsigned char c) {
    out += "\\x";
    out += hex_digits[c >> 4];
    out += hex_digits[c & 15];
}

bool is_continuation(unsigned char c) {
    return (c & 0xc0) == 0x80;
}

bool is_digit(char c) {
    return c >= '0' && c <= '9';
}

bool is_word_char(char c) {
    return is_digit(c) || (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '_' ||
           c == '.' || c == '+' || c == '-';
}

int hex_value(char c) {
    if (c >= '0' && c <= '9') return c - '0';
    if (c >= 'a' && c <= 'f') return c - 'a' + 10;
    if (c >= 'A' && c <= 'F') return c - 'A' + 10;
    return -1;
}

// The length of the UTF-8 sequence starting `s` (RFC 3629: no overlong
// forms, no surrogates, nothing past U+10FFFF), or 0 when it is invalid.
std::size_t utf8_length(std::string_view s) {
    const auto byte = [&](std::size_t i) {
        return i < s.size() ? static_cast<unsigned char>(s[i]) : 0u;
    };
    const unsigned c = byte(0);
    unsigned lo = 0x80;
    unsigned hi = 0xbf;
    std::size_t n = 0;
    if (c >= 0xc2 && c <= 0xdf) {
        n = 2;
    } else if (c >= 0xe0 && c <= 0xef) {
        n = 3;
        if (c == 0xe0) lo = 0xa0;
        if (c == 0xed) hi = 0x9f;
    } else if (c >= 0xf0 && c <= 0xf4) {
        n = 4;
        if (c == 0xf0) lo = 0x90;
        if (c == 0xf4) hi = 0x8f;
    } else {
        return 0;
    }
    if (byte(1) < lo || byte(1) > hi) return 0;
    for (std::size_t i = 2; i < n; ++i) {
        if (!is_continuation(static_cast<unsigned char>(byte(i)))) return 0;
    }
    return n;
}

void append_utf8(std::string& out, std::uint32_t code_point) {
    if (code_point < 0x80) {
        out += static_cast<char>(code_point);
    } else if (code_point < 0x800) {
        out += static_cast<char>(0xc0 | (code_point >> 6));
        out += static_cast<char>(0x80 | (code_point & 0x3f));
    } else if (code_point < 0x10000) {
        out += static_cast<char>(0xe0 | (code_point >> 12));
        out += static_cast<char>(0x80 | ((code_point >> 6) & 0x3f));
        out += static_cast<char>(0x80 | (code_point & 0x3f));
    } else {
        out += static_cast<char>(0xf0 | (code_point >> 18));
        out += static_cast<char>(0x80 | ((code_point >> 12) & 0x3f));
        out += static_cast<char>(0x80 | ((code_point >> 6) & 0x3f));
        out += static_cast<char>(0x80 | (code_point & 0x3f));
    }
}

// After from_chars reported a range error for the JSON number `t`: whether
// it was too large rather than too close to zero. Such errors need a
// decimal exponent beyond ±300, so the sign of the first significant
// digit's exponent decides, and a coarse count is enough.
bool overflows(std::string_view t) {
    std::size_t i = t.front() == '-' ? 1 : 0;
    const std::size_t int_start = i;
    while (i < t.size() && is_digit(t[i])) ++i;
    std::int64_t magnitude = static_cast<std::int64_t>(i - int_start) - 1;
    if (t[int_start] == '0') {
        magnitude = -1;
        if (i < t.size() && t[i] == '.') {
            ++i;
            while (i < t.size() && t[i] == '0') {
                --magnitude;
                ++i;
            }
        }
    }
    const std::size_t e = t.find_first_of("eE");
    if (e == std::string_view::npos) return magnitude > 0;
    i = e + 1;
    const bool negative = t[i] == '-';
    if (t[i] == '-' || t[i] == '+') ++i;
    constexpr std::int64_t saturated = std::int64_t{1} << 40;
    std::int64_t exponent = 0;
    for (; i < t.size() && exponent < saturated; ++i) exponent = exponent * 10 + (t[i] - '0');
    return magnitude + (negative ? -exponent : exponent) > 0;
}

class Parser {
public:
    Parser(std::string_view text, std::string_view source, const JsonOptions& options)
        : text_(text), source_(source), options_(options) {}

    ToolStatus document(JsonValue& out) {
        // A byte order mark is invisible in editors, so the column stays 1.
        if (text_.starts_with("\xef\xbb\xbf")) pos_ = 3;
        skip_whitespace();
        if (ToolStatus s = value(out, 0); !s) return s;
        skip_whitespace();
        if (!at_end()) return expected("the end of the text after the top-level value");
        return ToolStatus::ok();
    }

private:
    bool at_end() const { return pos_ == text_.size(); }
    // NUL at the end: no branch of the grammar accepts it.
    char peek() const { return at_end() ? '\0' : text_[pos_]; }

    void advance() {
        const auto c = static_cast<unsigned char>(text_[pos_++]);
        if (c == '\n') {
            ++here_.line;
            here_.column = 1;
        } else if (!is_continuation(c)) {
            ++here_.column;
        }
    }

    void skip_whitespace() {
        while (!at_end()) {
            const char c = peek();
            if (c != ' ' && c != '\t' && c != '\n' && c != '\r') return;
            advance();
        }
    }

    ToolStatus error(JsonPosition at, std::string_view what) const {
        std::string message = json_location(source_, at);
        message += what;
        return ToolStatus(DFM_ERROR_PARSE, std::move(message));
    }

    // "expected WHAT, found ..." describing what the cursor is on.
    ToolStatus expected(std::string_view what) const { return expected(here_, what); }
    ToolStatus expected(JsonPosition at, std::string_view what) const {
        std::string message = "expected ";
        message += what;
        message += ", found ";
        message += found();
        return error(at, message);
    }

    std::string found() const {
        if (at_end()) return "the end of the text";
        const char c = peek();
        const auto u = static_cast<unsigned char>(c);
        if (c == '\n' || c == '\r') return "a line break";
        std::string out;
        if (u < 0x20 || u >= 0x7f) {
            out = "the byte ";
            append_hex_byte(out, u);
            return out;
        }
        // A whole word reads better than its first letter: 'NaN', 'tru'.
        std::size_t end = pos_ + 1;
        if (is_word_char(c)) {
            while (end < text_.size() && end - pos_ < 32 && is_word_char(text_[end])) ++end;
        }
        out = "'";
        out += text_.substr(pos_, end - pos_);
        out += '\'';
        return out;
    }

    ToolStatus value(JsonValue& out, std::size_t depth) {
        out.at = here_;
        const char c = peek();
        if (c == '{' || c == '[') {
            if (depth == json_max_depth) {
                std::string what = "arrays and objects nest deeper than ";
                what += std::to_string(json_max_depth);
                what += " levels";
                return error(here_, what);
            }
            return c == '{' ? object(out, depth + 1) : array(out, depth + 1);
        }
        if (c == '"') {
            out.type = JsonType::string;
            return string(out.text);
        }
        if (c == '-' || is_digit(c)) return number(out);
        if (literal("true")) {
            out.type = JsonType::boolean;
            out.boolean = true;
        } else if (literal("false")) {
            out.type = JsonType::boolean;
        } else if (!literal("null")) {
            return expected("a value");
        }
        return ToolStatus::ok();
    }

    // Consumes `word` when the text continues with it as a whole word.
    bool literal(std::string_view word) {
        const std::string_view rest = text_.substr(pos_);
        if (!rest.starts_with(word)) return false;
        if (rest.size() > word.size() && is_word_char(rest[word.size()])) return false;
        for (std::size_t i = 0; i < word.size(); ++i) advance();
        return true;
    }

    void digits() {
        while (is_digit(peek())) advance();
    }

    ToolStatus number(JsonValue& out) {
        const std::size_t start = pos_;
        out.type = JsonType::number;
        out.integer = true;
        if (peek() == '-') advance();
        if (!is_digit(peek())) return expected("a digit after '-'");
        if (peek() == '0') {
            advance();
            if (is_digit(peek())) return error(out.at, "a number cannot start with a leading zero");
        } else {
            digits();
        }
        if (peek() == '.') {
            out.integer = false;
            advance();
            if (!is_digit(peek())) return expected("a digit after the decimal point");
            digits();
        }
        if (peek() == 'e' || peek() == 'E') {
            out.integer = false;
            advance();
            if (peek() == '+' || peek() == '-') advance();
            if (!is_digit(peek())) return expected("a digit in the exponent");
            digits();
        }
        const std::string_view t = text_.substr(start, pos_ - start);
        const std::errc ec = std::from_chars(t.data(), t.data() + t.size(), out.number).ec;
        if (ec == std::errc::result_out_of_range) {
            if (overflows(t) && options_.keep_huge_numbers) {
                out.beyond_double = true;
                out.number = t.front() == '-' ? -std::numeric_limits<double>::infinity()
                                              : std::numeric_limits<double>::infinity();
                out.text = std::string(t);
                return ToolStatus::ok();
            }
            if (overflows(t)) {
                std::string what = "the number ";
                what += json_printable(t);
                what += " is beyond the range of a double";
                return error(out.at, what);
            }
            out.number = t.front() == '-' ? -0.0 : 0.0;
        } else if (ec != std::errc()) {
            return error(out.at, "unreadable number");
        }
        return ToolStatus::ok();
    }

    ToolStatus string(std::string& out) {
        const JsonPosition open = here_;
        advance();
        for (;;) {
            if (at_end() || peek() == '\n') {
                std::string what = "'\"' to end the string started at ";
                what += std::to_string(open.line);
                what += ':';
                what += std::to_string(open.column);
                return expected(what);
            }
            const char c = peek();
            const auto u = static_cast<unsigned char>(c);
            if (c == '"') {
                advance();
                return ToolStatus::ok();
            }
            if (c == '\\') {
                if (ToolStatus s = escape(out); !s) return s;
            } else if (u < 0x20) {
                std::string what = "a control character (";
                append_hex_byte(what, u);
                what += ") must be written as an escape in a string";
                return error(here_, what);
            } else if (u < 0x80) {
                out += c;
                advance();
            } else {
                const std::size_t n = utf8_length(text_.substr(pos_));
                if (n == 0) {
                    std::string what = "invalid UTF-8 in a string at byte ";
                    append_hex_byte(what, u);
                    return error(here_, what);
                }
                out.append(text_.substr(pos_, n));
                for (std::size_t i = 0; i < n; ++i) advance();
            }
        }
    }

    ToolStatus escape(std::string& out) {
        const JsonPosition at = here_;
        advance();
        char decoded = '\0';
        switch (peek()) {
            case '"': decoded = '"'; break;
            case '\\': decoded = '\\'; break;
            case '/': decoded = '/'; break;
            case 'b': decoded = '\b'; break;
            case 'f': decoded = '\f'; break;
            case 'n': decoded = '\n'; break;
            case 'r': decoded = '\r'; break;
            case 't': decoded = '\t'; break;
            case 'u': return unicode_escape(out, at);
            default: return expected(at, "an escape after '\\' (one of \" \\ / b f n r t u)");
        }
        out += decoded;
        advance();
        return ToolStatus::ok();
    }

    // Reads the four hex digits of a \u escape, the cursor on the 'u'.
    ToolStatus code_unit(std::uint32_t& unit) {
        advance();
        unit = 0;
        for (int i = 0; i < 4; ++i) {
            const int v = hex_value(peek());
            if (v < 0) return expected("four hex digits after '\\u'");
            unit = unit * 16 + static_cast<std::uint32_t>(v);
            advance();
        }
        return ToolStatus::ok();
    }

    ToolStatus unicode_escape(std::string& out, JsonPosition at) {
        std::uint32_t unit = 0;
        if (ToolStatus s = code_unit(unit); !s) return s;
        const std::string_view written = text_.substr(pos_ - 6, 6);
        if (unit >= 0xdc00 && unit <= 0xdfff) {
            std::string what = "the low surrogate ";
            what += written;
            what += " must follow a high surrogate (\\uD800 to \\uDBFF)";
            return error(at, what);
        }
        if (unit >= 0xd800 && unit <= 0xdbff) {
            const JsonPosition low_at = here_;
            const bool escaped = text_.substr(pos_).starts_with("\\u");
            std::uint32_t low = 0;
            if (escaped) {
                advance();
                if (ToolStatus s = code_unit(low); !s) return s;
            }
            if (low < 0xdc00 || low > 0xdfff) {
                std::string what = "the high surrogate ";
                what += written;
                what += " must be followed by a low surrogate (\\uDC00 to \\uDFFF)";
                return error(escaped ? low_at : at, what);
            }
            unit = 0x10000 + ((unit - 0xd800) << 10) + (low - 0xdc00);
        }
        append_utf8(out, unit);
        return ToolStatus::ok();
    }

    ToolStatus array(JsonValue& out, std::size_t depth) {
        out.type = JsonType::array;
        advance();
        skip_whitespace();
        if (peek() == ']') {
            advance();
            return ToolStatus::ok();
        }
        for (;;) {
            out.items.emplace_back();
            if (ToolStatus s = value(out.items.back(), depth); !s) return s;
            skip_whitespace();
            if (peek() == ']') {
                advance();
                return ToolStatus::ok();
            }
            if (peek() != ',') return expected("',' or ']' after an array element");
            advance();
            skip_whitespace();
        }
    }

    ToolStatus object(JsonValue& out, std::size_t depth) {
        out.type = JsonType::object;
        advance();
        skip_whitespace();
        if (peek() == '}') {
            advance();
            return ToolStatus::ok();
        }
        // Copies of the keys: the members' own strings move as the vector grows.
        std::unordered_set<std::string> keys;
        for (;;) {
            if (peek() != '"') {
                return expected(out.members.empty() ? "a string key or '}'"
                                                    : "a string key after ','");
            }
            JsonMember& m = out.members.emplace_back();
            m.at = here_;
            if (ToolStatus s = string(m.key); !s) return s;
            if (!keys.insert(m.key).second) return duplicate_key(out.members);
            skip_whitespace();
            if (peek() != ':') return expected("':' after an object key");
            advance();
            skip_whitespace();
            if (ToolStatus s = value(m.value, depth); !s) return s;
            skip_whitespace();
            if (peek() == '}') {
                advance();
                return ToolStatus::ok();
            }
            if (peek() != ',') return expected("',' or '}' after an object member");
            advance();
            skip_whitespace();
        }
    }

    // The last of `members` repeats an earlier key.
    ToolStatus duplicate_key(const std::vector<JsonMember>& members) const {
        const JsonMember& again = members.back();
        JsonPosition first;
        for (const JsonMember& m : members) {
            if (m.key == again.key) {
                first = m.at;
                break;
            }
        }
        std::string what = "duplicate key \"";
        what += json_printable(again.key);
        what += "\" (first at ";
        what += std::to_string(first.line);
        what += ':';
        what += std::to_string(first.column);
        what += ')';
        return error(again.at, what);
    }

    std::string_view text_;
    std::string_view source_;
    JsonOptions options_;
    std::size_t pos_ = 0;
    JsonPosition here_;
};

}  // namespace

const char* json_type_phrase(JsonType type) {
    switch (type) {
        case JsonType::null: return "null";
        case JsonType::boolean: return "a boolean";
        case JsonType::number: return "a number";
        case JsonType::string: return "a string";
        case JsonType::array: return "an array";
        case JsonType::object: return "an object";
    }
    return "an unknown value";
}

std::string json_location(std::string_view source, JsonPosition at) {
    std::string out(source);
    out += ':';
    out += std::to_string(at.line);
    out += ':';
    out += std::to_string(at.column);
    out += ": ";
    return out;
}

std::string json_printable(std::string_view text) {
    constexpr std::size_t max_chars = 40;
    std::string out;
    std::size_t chars = 0;
    for (const char ch : text) {
        const auto c = static_cast<unsigned char>(ch);
        if (!is_continuation(c) && chars++ == max_chars) {
            out += "...";
            break;
        }
        if (c < 0x20 || c == 0x7f) {
            append_hex_byte(out, c);
        } else {
            out += ch;
        }
    }
    return out;
}

const JsonMember* JsonValue::find(std::string_view key) const {
    for (const JsonMember& m : members) {
        if (m.key == key) return &m;
    }
    return nullptr;
}

ToolStatus parse_json(std::string_view text, std::string_view source, JsonValue& out) {
    return parse_json(text, source, JsonOptions{}, out);
}

ToolStatus parse_json(std::string_view text, std::string_view source, const JsonOptions& options,
                      JsonValue& out) {
    out = JsonValue{};
    try {
        JsonValue root;
        Parser parser(text, source, options);
        if (ToolStatus s = parser.document(root); !s) return s;
        out = std::move(root);
        return ToolStatus::ok();
    } catch (const std::bad_alloc&) {
        std::string message(source);
        message += ": out of memory while reading JSON";
        return ToolStatus(DFM_ERROR_OUT_OF_MEMORY, std::move(message));
    }
}

}  // namespace dfm::json
