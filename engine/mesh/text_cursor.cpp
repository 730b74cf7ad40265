#include "mesh/text_cursor.hpp"

#include <charconv>
#include <cmath>
#include <string>

namespace dfm::mesh {

bool is_space(char c) {
    return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\v' || c == '\f';
}

namespace {

std::string_view trim(std::string_view s) {
    while (!s.empty() && is_space(s.front())) s.remove_prefix(1);
    while (!s.empty() && is_space(s.back())) s.remove_suffix(1);
    return s;
}

}  // namespace

bool TextCursor::next_line(std::string_view& line) {
    while (pos_ < text_.size()) {
        const std::size_t end = text_.find('\n', pos_);
        const std::size_t stop = end == std::string_view::npos ? text_.size() : end;
        std::string_view raw = text_.substr(pos_, stop - pos_);
        pos_ = end == std::string_view::npos ? text_.size() : end + 1;
        line_ = next_line_++;
        if (comment_ != '\0') {
            const std::size_t c = raw.find(comment_);
            if (c != std::string_view::npos) raw = raw.substr(0, c);
        }
        raw = trim(raw);
        if (!raw.empty()) {
            line = raw;
            return true;
        }
    }
    return false;
}

void TextCursor::skip_blanks() {
    while (pos_ < text_.size()) {
        const char c = text_[pos_];
        if (c == '\n') {
            ++next_line_;
            ++pos_;
        } else if (is_space(c)) {
            ++pos_;
        } else if (comment_ != '\0' && c == comment_) {
            while (pos_ < text_.size() && text_[pos_] != '\n') ++pos_;
        } else {
            return;
        }
    }
}

bool TextCursor::next_token(std::string_view& token) {
    skip_blanks();
    if (pos_ == text_.size()) {
        // At the end, name the last line the text has, not the empty one
        // after its final line break.
        const bool ends_with_break = !text_.empty() && text_.back() == '\n';
        line_ = ends_with_break && next_line_ > 1 ? next_line_ - 1 : next_line_;
        return false;
    }
    line_ = next_line_;
    const std::size_t start = pos_;
    while (pos_ < text_.size() && !is_space(text_[pos_]) &&
           !(comment_ != '\0' && text_[pos_] == comment_)) {
        ++pos_;
    }
    token = text_.substr(start, pos_ - start);
    return true;
}

bool Tokens::next(std::string_view& token) {
    while (!rest_.empty() && is_space(rest_.front())) rest_.remove_prefix(1);
    if (rest_.empty()) return false;
    std::size_t n = 0;
    while (n < rest_.size() && !is_space(rest_[n])) ++n;
    token = rest_.substr(0, n);
    rest_.remove_prefix(n);
    return true;
}

std::size_t Tokens::count_remaining() const {
    Tokens copy = *this;
    std::size_t n = 0;
    std::string_view t;
    while (copy.next(t)) ++n;
    return n;
}

NumberError parse_double(std::string_view token, double& value) {
    if (!token.empty() && token.front() == '+') token.remove_prefix(1);
    if (token.empty()) return NumberError::not_a_number;
    const char* first = token.data();
    const char* last = first + token.size();
    const auto [ptr, ec] = std::from_chars(first, last, value, std::chars_format::general);
    if (ec == std::errc::result_out_of_range) return NumberError::too_large;
    if (ec != std::errc() || ptr != last) return NumberError::not_a_number;
    if (!std::isfinite(value)) return NumberError::not_finite;
    return NumberError::none;
}

NumberError parse_integer(std::string_view token, std::int64_t& value) {
    if (!token.empty() && token.front() == '+') token.remove_prefix(1);
    if (token.empty()) return NumberError::not_an_integer;
    const char* first = token.data();
    const char* last = first + token.size();
    const auto [ptr, ec] = std::from_chars(first, last, value);
    if (ec == std::errc::result_out_of_range) return NumberError::too_large;
    if (ec != std::errc() || ptr != last) return NumberError::not_an_integer;
    return NumberError::none;
}

std::string_view describe_number_error(NumberError error) {
    switch (error) {
        case NumberError::none: return "valid";
        case NumberError::not_a_number: return "not a number";
        case NumberError::not_finite: return "not a finite number";
        case NumberError::not_an_integer: return "not an integer";
        case NumberError::too_large: return "out of the representable range";
    }
    return "invalid";
}

std::string quote_token(std::string_view token) {
    constexpr std::size_t max_shown = 32;
    std::string out = "'";
    for (std::size_t i = 0; i < token.size() && i < max_shown; ++i) {
        const unsigned char c = static_cast<unsigned char>(token[i]);
        if (c >= 0x20 && c < 0x7f && c != '\'') {
            out += static_cast<char>(c);
        } else {
            static constexpr char hex[] = "0123456789abcdef";
            out += "\\x";
            out += hex[c >> 4];
            out += hex[c & 15];
        }
    }
    if (token.size() > max_shown) out += "...";
    out += '\'';
    return out;
}

}  // namespace dfm::mesh
