#pragma once

#include <cmath>
#include <cstdio>
#include <string>
#include <string_view>
#include <vector>

namespace dfm::solver_bench {

// A small pretty-printing JSON writer: keys and values alternate inside
// objects; non-finite numbers are written as null.
class Json {
public:
    Json& begin_object() { return open('{'); }
    Json& end_object() { return close('}'); }
    Json& begin_array() { return open('['); }
    Json& end_array() { return close(']'); }

    Json& key(std::string_view name) {
        separate();
        quote(name);
        out_ += ": ";
        after_key_ = true;
        return *this;
    }

    Json& value(double v) {
        separate();
        if (!std::isfinite(v)) {
            out_ += "null";
            return *this;
        }
        char buffer[32];
        std::snprintf(buffer, sizeof buffer, "%.6g", v);
        out_ += buffer;
        return *this;
    }
    Json& value(std::size_t v) {
        separate();
        out_ += std::to_string(v);
        return *this;
    }
    Json& value(bool v) {
        separate();
        out_ += v ? "true" : "false";
        return *this;
    }
    Json& value(std::string_view v) {
        separate();
        quote(v);
        return *this;
    }
    Json& value(const char* v) { return value(std::string_view(v)); }

    template <class T>
    Json& field(std::string_view name, T v) {
        return key(name).value(v);
    }

    const std::string& str() const { return out_; }

private:
    Json& open(char c) {
        separate();
        out_ += c;
        has_items_.push_back(false);
        return *this;
    }
    Json& close(char c) {
        const bool had = has_items_.back();
        has_items_.pop_back();
        if (had) newline();
        out_ += c;
        return *this;
    }
    void separate() {
        if (after_key_) {
            after_key_ = false;
            return;
        }
        if (has_items_.empty()) return;
        if (has_items_.back()) out_ += ',';
        has_items_.back() = true;
        newline();
    }
    void newline() {
        out_ += '\n';
        out_.append(2 * has_items_.size(), ' ');
    }
    void quote(std::string_view s) {
        out_ += '"';
        for (const char c : s) {
            if (c == '"' || c == '\\') out_ += '\\';
            out_ += c;
        }
        out_ += '"';
    }

    std::string out_;
    std::vector<bool> has_items_;
    bool after_key_ = false;
};

}  // namespace dfm::solver_bench
