#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace dfm::cli {

// Writes one compact JSON value. Keys and values alternate inside objects;
// non-finite numbers come out as null, since JSON has no word for them.
class JsonWriter {
public:
    JsonWriter& begin_object();
    JsonWriter& end_object();
    JsonWriter& begin_array();
    JsonWriter& end_array();
    JsonWriter& key(std::string_view name);
    JsonWriter& value(double v);
    JsonWriter& value(std::uint64_t v);
    JsonWriter& value(bool v);
    JsonWriter& value(std::string_view v);
    JsonWriter& value(const char* v) { return value(std::string_view(v)); }

    const std::string& str() const { return out_; }

private:
    void separate();

    std::string out_;
    std::vector<bool> has_items_;
    bool after_key_ = false;
};

}  // namespace dfm::cli
