#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/status.hpp"

namespace dfm::mesh::ply {

enum class Encoding { ascii, binary_little_endian, binary_big_endian };

enum class Scalar { int8, uint8, int16, uint16, int32, uint32, float32, float64 };

std::size_t scalar_size(Scalar type);
bool scalar_is_integer(Scalar type);

struct Property {
    std::string name;
    Scalar type = Scalar::float32;  // the item type, for lists
    bool is_list = false;
    Scalar count_type = Scalar::uint8;
};

struct Element {
    std::string name;
    std::uint64_t count = 0;
    std::vector<Property> properties;
    std::uint64_t line = 0;  // where the header declares it
};

struct Header {
    Encoding encoding = Encoding::ascii;
    std::vector<Element> elements;
    std::size_t body_offset = 0;        // first byte after "end_header"
    std::uint64_t body_first_line = 0;  // the body's first line, for ascii
};

// Parses the header at the start of `bytes`, checking every line.
Status parse_header(std::string_view bytes, std::string_view source, Header& header);

}  // namespace dfm::mesh::ply
