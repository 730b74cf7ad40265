#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

namespace dfm::mesh {

// Walks a text buffer by lines or by whitespace-separated tokens, keeping the
// 1-based number of the line it is on. `comment` (if not '\0') starts a
// comment that runs to the end of the line.
class TextCursor {
public:
    // `first_line` numbers the text's first line, for text that starts
    // inside a file (a PLY body after its header).
    explicit TextCursor(std::string_view text, char comment = '\0', std::uint64_t first_line = 1)
        : text_(text), comment_(comment), next_line_(first_line) {}

    // The next line holding anything but blanks and comments, without its
    // comment and surrounding whitespace. False at the end of the text.
    bool next_line(std::string_view& line);

    // The next token, crossing line ends and skipping comments.
    bool next_token(std::string_view& token);

    // Steps over blanks and comments; then upcoming_line() is the line of
    // the next token.
    void skip_blanks();
    std::uint64_t upcoming_line() const { return next_line_; }

    std::uint64_t line() const { return line_; }
    std::size_t offset() const { return pos_; }
    std::size_t remaining_bytes() const { return text_.size() - pos_; }

private:
    std::string_view text_;
    char comment_;
    std::size_t pos_ = 0;
    std::uint64_t line_ = 0;  // the line of the last thing returned
    std::uint64_t next_line_ = 1;
};

// Splits one line into whitespace-separated tokens.
class Tokens {
public:
    explicit Tokens(std::string_view line) : rest_(line) {}
    bool next(std::string_view& token);
    std::size_t count_remaining() const;

private:
    std::string_view rest_;
};

bool is_space(char c);

enum class NumberError { none, not_a_number, not_finite, not_an_integer, too_large };

// Whole-token parses: trailing characters make the token invalid.
NumberError parse_double(std::string_view token, double& value);
NumberError parse_integer(std::string_view token, std::int64_t& value);

std::string_view describe_number_error(NumberError error);

// A short, printable rendering of a token for messages (cut and escaped).
std::string quote_token(std::string_view token);

}  // namespace dfm::mesh
