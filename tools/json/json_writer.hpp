#pragma once

#include <concepts>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace dfm::json {

// Appends the shortest text that reads back as exactly `value`.
void append_number(std::string& out, double value);

// Writes one JSON value, compact (what the tools print, one line) or
// indented (files a person reads). Keys and values alternate inside objects;
// strings are escaped (quotes, backslashes, control characters), numbers are
// the shortest text that reads back as the same double, and non-finite
// numbers come out as null, since JSON has no word for them.
class JsonWriter {
public:
    enum class Layout { compact, indented };

    explicit JsonWriter(Layout layout = Layout::compact) : layout_(layout) {}

    JsonWriter& begin_object();
    JsonWriter& end_object();
    JsonWriter& begin_array();
    JsonWriter& end_array();
    JsonWriter& key(std::string_view name);
    JsonWriter& value(double v);
    JsonWriter& value(bool v);
    JsonWriter& value(std::string_view v);
    JsonWriter& value(const char* v) { return value(std::string_view(v)); }
    JsonWriter& value(const std::string& v) { return value(std::string_view(v)); }
    template <std::integral T>
    requires(!std::same_as<T, bool>) JsonWriter& value(T v) {
        separate();
        out_ += std::to_string(v);
        return *this;
    }
    // An array of numbers: [x, y, z] and the like.
    template <class Number>
    JsonWriter& numbers(const Number* v, std::size_t count) {
        begin_array();
        for (std::size_t i = 0; i < count; ++i) value(v[i]);
        return end_array();
    }

    // key(name).value(v)
    template <class T>
    JsonWriter& field(std::string_view name, const T& v) {
        return key(name).value(v);
    }

    const std::string& str() const { return out_; }

private:
    void separate();
    void open(char bracket);
    void close(char bracket);
    void newline();

    Layout layout_;
    std::string out_;
    std::vector<bool> has_items_;
    bool after_key_ = false;
};

}  // namespace dfm::json
