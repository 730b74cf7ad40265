#pragma once

#include <cstdint>
#include <string>
#include <string_view>

#include "core/status.hpp"

namespace dfm::mesh {

// A position in an input file, for error messages: "cow.off:12: " for text,
// "cow.ply: byte 4096: " for binary data.
struct Where {
    std::string_view source;
    std::uint64_t position = 0;
    bool is_byte_offset = false;

    static Where line(std::string_view source, std::uint64_t line) { return {source, line, false}; }
    static Where byte(std::string_view source, std::uint64_t offset) {
        return {source, offset, true};
    }

    std::string prefix() const;
    Status error(Errc code, std::string_view what) const;
    Status parse_error(std::string_view what) const { return error(Errc::parse_error, what); }
};

}  // namespace dfm::mesh
