#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/status.hpp"
#include "mesh/fbx_document.hpp"

// Decodes the values of an FbxDocument's properties, binary or ASCII.
namespace dfm::mesh {

// A scalar number (binary Y C I F D L, ASCII number); nullopt for any other
// property.
std::optional<double> fbx_number(const FbxDocument& doc, const FbxProperty& p);
// An integer (binary Y C I L, an ASCII number without fraction or exponent).
std::optional<std::int64_t> fbx_integer(const FbxDocument& doc, const FbxProperty& p);
// A string (binary S, ASCII quoted), as its bytes are.
std::optional<std::string_view> fbx_string(const FbxDocument& doc, const FbxProperty& p);

// An object's name without its class: binary "Name\0\1Class", ASCII
// "Class::Name".
std::string_view fbx_object_name(std::string_view stored);

// The values of a node that holds an array of numbers: its one property, a
// binary f d i l b c array (a deflated one inflated, its exact size checked)
// or an ASCII array; or, when it holds only scalar numbers, those. The error
// names the node. Allocates at most the array's declared size.
Status fbx_doubles(const FbxDocument& doc, const FbxNode& node, std::vector<double>& out);
// The same as integers: a binary i l b c array, or ASCII values that are
// whole numbers within 64 bits.
Status fbx_integers(const FbxDocument& doc, const FbxNode& node, std::vector<std::int64_t>& out);

// How many values fbx_doubles would give for `node`, without decoding them:
// its one array's declared count, or its number of properties.
std::size_t fbx_value_count(const FbxDocument& doc, const FbxNode& node);

// Checks that a binary array property stores exactly its declared size
// (inflating a deflated one through a small buffer, so nothing of the
// declared size is allocated). Other properties pass.
Status fbx_check_array(const FbxDocument& doc, const FbxNode& node, const FbxProperty& p);

}  // namespace dfm::mesh
