#include <algorithm>
#include <charconv>
#include <cmath>

#include "mesh/fbx_document.hpp"

// ASCII FBX 7.x: "; comment" lines, nodes "Name: value, value, ... { ... }"
// whose values are numbers, "quoted strings" and bare words, and arrays
// "*N { a: v, v, ... }". The array becomes one property of its node (type
// 'a'), so the tree has the binary format's shape.
namespace dfm::mesh {

namespace {

enum class Kind { end, key, data, comma, open, close };

struct Token {
    Kind kind = Kind::end;
    std::size_t begin = 0;  // a key's name, a string's inside, a word
    std::size_t end = 0;
    std::uint32_t line = 1;
    bool quoted = false;
};

bool is_delimiter(char c) {
    return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == ',' || c == '{' || c == '}' ||
           c == '"' || c == ';' || c == ':';
}

bool is_number(std::string_view text) {
    double value = 0.0;
    const char* first = text.data();
    if (!text.empty() && text.front() == '+') ++first;
    const auto [ptr, ec] = std::from_chars(first, text.data() + text.size(), value);
    return ec == std::errc() && ptr == text.data() + text.size() && first != ptr;
}

class AsciiParser {
public:
    explicit AsciiParser(FbxDocument& doc) : doc_(doc), b_(doc.bytes) {}

    Status parse() {
        if (Status s = advance(); !s) return s;
        if (Status s = list(no_index, 1, 0); !s) return s;
        return Status::ok();
    }

private:
    Status error(std::uint32_t line, const std::string& what) const {
        return Where::line(doc_.source, line).parse_error(what);
    }

    // Reads the next token into `next_`.
    Status advance() {
        std::size_t& p = pos_;
        while (p < b_.size()) {
            const char c = b_[p];
            if (c == '\n') {
                ++line_;
                ++p;
            } else if (c == ' ' || c == '\t' || c == '\r') {
                ++p;
            } else if (c == ';') {
                while (p < b_.size() && b_[p] != '\n') ++p;
            } else {
                break;
            }
        }
        next_ = Token{};
        next_.line = line_;
        next_.begin = p;
        if (p == b_.size()) return Status::ok();
        const char c = b_[p];
        if (c == ',' || c == '{' || c == '}') {
            next_.kind = c == ',' ? Kind::comma : (c == '{' ? Kind::open : Kind::close);
            next_.end = ++p;
            return Status::ok();
        }
        if (c == '"') {
            const std::size_t close = b_.find('"', p + 1);
            if (close == std::string::npos) {
                return error(line_, "a string opened here is never closed");
            }
            for (std::size_t i = p + 1; i < close; ++i) line_ += b_[i] == '\n';
            next_.kind = Kind::data;
            next_.quoted = true;
            next_.begin = p + 1;
            next_.end = close;
            p = close + 1;
            return Status::ok();
        }
        if (c == ':') return error(line_, "a ':' without a name before it");
        while (p < b_.size() && !is_delimiter(b_[p])) {
            // Control characters outside strings: Assimp splits tokens at
            // some of them (a form feed ends its line), so none is taken.
            if (static_cast<unsigned char>(b_[p]) < 0x20) {
                static constexpr char hex[] = "0123456789abcdef";
                const auto code = static_cast<unsigned char>(b_[p]);
                return error(line_, std::string("a control character 0x") + hex[code >> 4] +
                                        hex[code & 15] + " outside a string");
            }
            ++p;
        }
        next_.end = p;
        if (p < b_.size() && b_[p] == ':') {
            next_.kind = Kind::key;
            ++p;
        } else {
            next_.kind = Kind::data;
        }
        return Status::ok();
    }

    std::string text(const Token& t) const {
        std::string out;
        for (char c :
             std::string_view(b_).substr(t.begin, std::min<std::size_t>(t.end - t.begin, 40))) {
            out += (c >= 0x20 && c < 0x7f) ? c : '?';
        }
        return out;
    }

    // Nodes until '}' (inside a node, `open_line` is where its '{' was) or
    // the end of the file (the top level).
    Status list(std::uint32_t parent, std::size_t depth, std::uint32_t open_line) {
        while (true) {
            if (next_.kind == Kind::end) {
                if (parent == no_index) return Status::ok();
                return error(next_.line, "the file ends inside the '{' opened at line " +
                                             std::to_string(open_line));
            }
            if (next_.kind == Kind::close) {
                if (parent == no_index) return error(next_.line, "a '}' closes nothing");
                return advance();
            }
            if (next_.kind != Kind::key) {
                return error(next_.line,
                             "expected a node name ('Name:'), found '" + text(next_) + "'");
            }
            if (Status s = node(parent, depth); !s) return s;
        }
    }

    Status node(std::uint32_t parent, std::size_t depth) {
        const Token key = next_;
        if (depth > fbx_max_depth) {
            return error(key.line,
                         "nodes nest deeper than " + std::to_string(fbx_max_depth) + " levels");
        }
        FbxNode n;
        n.name = std::string_view(b_).substr(key.begin, key.end - key.begin);
        n.parent = parent;
        n.begin = key.begin;
        n.line = key.line;
        n.first_property = static_cast<std::uint32_t>(doc_.properties.size());
        const std::uint32_t index = static_cast<std::uint32_t>(doc_.nodes.size());
        doc_.nodes.push_back(std::move(n));
        if (parent == no_index) {
            doc_.roots.push_back(index);
        } else {
            doc_.nodes[parent].children.push_back(index);
        }
        if (Status s = advance(); !s) return s;
        bool expect_value = true;
        while (next_.kind == Kind::data || next_.kind == Kind::comma) {
            if (next_.kind == Kind::comma) {
                if (expect_value) return error(next_.line, "a ',' where a value belongs");
                expect_value = true;
                if (Status s = advance(); !s) return s;
                continue;
            }
            // Values are separated by commas (Assimp's parser refuses two
            // in a row, and leaks what it parsed when it does).
            if (!expect_value) {
                return error(next_.line, "a value '" + text(next_) +
                                             "' follows another without a ',' between them");
            }
            const bool array =
                next_.end - next_.begin > 1 && b_[next_.begin] == '*' && !next_.quoted;
            if (Status s = value(); !s) return s;
            ++doc_.nodes[index].property_count;
            expect_value = false;
            // An array's '}' ends its node for Assimp: nothing may follow it.
            if (array && (next_.kind == Kind::data || next_.kind == Kind::comma ||
                          next_.kind == Kind::open)) {
                return error(next_.line,
                             "an array ends its node, and '" + text(next_) + "' follows it");
            }
        }
        if (next_.kind == Kind::open) {
            const std::uint32_t open_line = next_.line;
            if (Status s = advance(); !s) return s;
            return list(index, depth + 1, open_line);
        }
        // Assimp's parser wants a node's values followed by something: a
        // file ends with a '}'.
        if (next_.kind == Kind::end) {
            return error(key.line, "the file ends right after node '" + text(key) +
                                       "' (an FBX file ends with a node's closing '}')");
        }
        return Status::ok();
    }

    // One value: a number, string or word, or an array "*N { a: ... }".
    Status value() {
        const Token t = next_;
        const std::string_view word = std::string_view(b_).substr(t.begin, t.end - t.begin);
        FbxProperty prop;
        prop.begin = t.begin;
        prop.end = t.end;
        if (t.quoted) {
            prop.type = 's';
        } else if (word.size() > 1 && word.front() == '*') {
            return array(t, word.substr(1));
        } else {
            prop.type = is_number(word) ? 'n' : 'w';
        }
        doc_.properties.push_back(prop);
        return advance();
    }

    Status array(const Token& star, std::string_view digits) {
        std::uint64_t count = 0;
        const auto [ptr, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), count);
        if (ec != std::errc() || ptr != digits.data() + digits.size() || count > 0xFFFFFFFFu) {
            return error(star.line, "array length '*" + std::string(digits) + "' is not a count");
        }
        if (Status s = advance(); !s) return s;
        if (next_.kind != Kind::open) {
            return error(next_.line, "an array '*" + std::string(digits) + "' without its '{'");
        }
        if (Status s = advance(); !s) return s;
        if (next_.kind != Kind::key) {
            return error(next_.line, "an array's values must follow 'a:'");
        }
        if (Status s = advance(); !s) return s;
        FbxProperty prop;
        prop.type = 'a';
        prop.begin = next_.begin;
        prop.end = next_.begin;
        std::uint64_t found = 0;
        bool expect_value = true;
        while (next_.kind == Kind::data || next_.kind == Kind::comma) {
            if (next_.kind == Kind::comma) {
                if (expect_value) return error(next_.line, "a ',' where an array value belongs");
                expect_value = true;
            } else {
                if (!expect_value) {
                    return error(next_.line, "array value " + std::to_string(found) +
                                                 " follows another without a ',' between them");
                }
                const std::string_view v =
                    std::string_view(b_).substr(next_.begin, next_.end - next_.begin);
                if (next_.quoted || !is_number(v)) {
                    return error(next_.line, "array value " + std::to_string(found) + ": '" +
                                                 text(next_) + "' is not a number");
                }
                ++found;
                expect_value = false;
                prop.end = next_.end;
            }
            if (Status s = advance(); !s) return s;
        }
        if (next_.kind != Kind::close) {
            return error(next_.line, "an array's values must end with '}'");
        }
        if (found != count) {
            return error(star.line, "an array declared '*" + std::to_string(count) + "' has " +
                                        std::to_string(found) + " values");
        }
        prop.count = static_cast<std::uint32_t>(count);
        doc_.properties.push_back(prop);
        return advance();
    }

    FbxDocument& doc_;
    const std::string& b_;
    std::size_t pos_ = 0;
    std::uint32_t line_ = 1;
    Token next_;
};

// "; FBX 7.4.0 project file" -> 7400; 0 when absent.
std::uint32_t header_version(std::string_view text) {
    if (text.starts_with("\xEF\xBB\xBF")) text.remove_prefix(3);
    if (!text.starts_with("; FBX ")) return 0;
    text.remove_prefix(6);
    unsigned major = 0, minor = 0, patch = 0;
    auto r = std::from_chars(text.data(), text.data() + text.size(), major);
    if (r.ec != std::errc() || r.ptr == text.data() + text.size() || *r.ptr != '.') return 0;
    r = std::from_chars(r.ptr + 1, text.data() + text.size(), minor);
    if (r.ec != std::errc() || r.ptr == text.data() + text.size() || *r.ptr != '.') return 0;
    r = std::from_chars(r.ptr + 1, text.data() + text.size(), patch);
    if (r.ec != std::errc() || major > 9 || minor > 9 || patch > 99) return 0;
    return major * 1000 + minor * 100 + patch;
}

}  // namespace

Status parse_fbx_ascii(std::string bytes, std::string source, FbxDocument& out) {
    out = FbxDocument{};
    out.source = std::move(source);
    out.bytes = std::move(bytes);
    out.binary = false;
    const Where start = Where::line(out.source, 1);
    // Text has no NUL: Assimp's tokenizer would stop there, mid-file.
    if (const std::size_t nul = out.bytes.find('\0'); nul != std::string::npos) {
        const auto line = 1 + std::count(out.bytes.begin(), out.bytes.begin() + nul, '\n');
        return Where::line(out.source, static_cast<std::uint64_t>(line))
            .parse_error("a NUL byte in ASCII FBX text");
    }
    out.version = header_version(out.bytes);
    if (out.version == 0) {
        return start.parse_error(
            "not an FBX file (neither the binary magic nor an ASCII '; FBX 7.x.x' header)");
    }
    if (out.version < 7100 || out.version >= 8000) {
        return start.error(Errc::unsupported,
                           "FBX version " + std::to_string(out.version) +
                               " is not supported (ASCII FBX 7.1 to 7.7 is read)");
    }
    Status s = AsciiParser(out).parse();
    if (!s) {
        const std::string source_name = std::move(out.source);
        out = FbxDocument{};
        out.source = source_name;
    }
    return s;
}

}  // namespace dfm::mesh
