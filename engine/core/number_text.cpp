#include "core/number_text.hpp"

#include <charconv>

namespace dfm {

namespace {

template <typename T>
void append_shortest(std::string& out, T value) {
    char buf[32];
    const auto [end, ec] = std::to_chars(buf, buf + sizeof buf, value);
    out.append(buf, ec == std::errc() ? end : buf);
}

}  // namespace

void append_number(std::string& out, double value) {
    append_shortest(out, value);
}
void append_number(std::string& out, float value) {
    append_shortest(out, value);
}

void append_numbers(std::string& out, const glm::dvec3& v) {
    append_number(out, v.x);
    out += ' ';
    append_number(out, v.y);
    out += ' ';
    append_number(out, v.z);
}

}  // namespace dfm
