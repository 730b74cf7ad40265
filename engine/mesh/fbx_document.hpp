#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "core/status.hpp"
#include "mesh/mesh.hpp"
#include "mesh/where.hpp"

// An FBX file's node tree as the file holds it: every node's name, the
// places of its properties in the file's bytes and its children, nothing
// decoded yet (fbx_values.hpp decodes). Binary FBX 7.x (32-bit node headers
// up to 7.4, 64-bit from 7.5) and ASCII FBX 7.x parse into the same tree.
namespace dfm::mesh {

// One property of a node. Binary: `type` is the file's type code (Y C I F D
// L scalars, S R strings and raw bytes, f d l i b c arrays) and [begin, end)
// the value after it (for an array, its 12-byte header and its stored bytes).
// ASCII: 'n' a number, 's' a quoted string (begin and end inside the
// quotes), 'w' a bare word, 'a' an array "*N { a: ... }" (begin and end
// around the values).
struct FbxProperty {
    char type = 0;
    std::uint32_t count = 0;     // an array's elements
    std::uint32_t encoding = 0;  // a binary array's: 0 stored as is, 1 deflated
    std::size_t begin = 0;
    std::size_t end = 0;
};

struct FbxNode {
    std::string_view name;  // into FbxDocument::bytes
    std::uint32_t parent = no_index;
    std::uint32_t first_property = 0;  // into FbxDocument::properties
    std::uint32_t property_count = 0;
    std::vector<std::uint32_t> children;
    // Binary: the node's record [begin, end) and where its properties end;
    // `null_record` when its nested list is closed by a null record (a node
    // with children always is; one without may be). ASCII: `begin` is where
    // its name starts.
    std::size_t begin = 0;
    std::size_t end = 0;
    std::size_t properties_end = 0;
    bool null_record = false;
    std::uint32_t line = 0;  // ASCII: the line of its name (1-based)
};

struct FbxDocument {
    std::string source;  // names the file in messages
    std::string bytes;   // the whole file, as read
    bool binary = true;
    std::uint32_t version = 0;  // 7400 for FBX 7.4
    std::vector<FbxNode> nodes;
    std::vector<FbxProperty> properties;
    std::vector<std::uint32_t> roots;
    std::size_t footer = 0;  // binary: where the top-level null record ends

    const FbxProperty& property(const FbxNode& node, std::size_t i) const {
        return properties[node.first_property + i];
    }
    // The first child of `node` (no_index: the roots) named `name`, or null.
    const FbxNode* child(std::uint32_t node, std::string_view name) const;
    std::uint32_t index_of(const FbxNode& node) const {
        return static_cast<std::uint32_t>(&node - nodes.data());
    }
    // Where a node starts, for messages: "FILE: byte N: " or "FILE:LINE: ".
    Where where(const FbxNode& node) const;
    // "Objects/Geometry/Vertices": the node's names from the root.
    std::string path(const FbxNode& node) const;
    // where(node) + "node PATH: " + what.
    Status error(Errc code, const FbxNode& node, std::string_view what) const;
};

// The magic that opens a binary FBX file.
inline constexpr std::string_view fbx_binary_magic{"Kaydara FBX Binary  \0\x1a\0", 23};

// Nodes nest at most this deep; FBX's own files nest fewer than 10 levels.
inline constexpr std::size_t fbx_max_depth = 64;

// The bytes of one element of a binary array of type code `type` (f d l i
// b c); 0 for any other code.
std::size_t fbx_array_width(char type);

// Whether `head` starts like an FBX file: the binary magic, or ASCII FBX's
// "; FBX" header comment.
bool looks_like_fbx(std::string_view head);

// Parses the node tree of a binary FBX file (versions 7100 to 7700). Every
// node's record must lie inside its parent's and the file, its properties
// fill exactly their declared length, arrays hold what their headers say
// (a deflated one not beyond what its compressed bytes can inflate to;
// fbx_values.hpp checks the exact size), nesting is bounded. Errors name the
// byte offset and the node's path. Never throws but for std::bad_alloc.
Status parse_fbx_binary(std::string bytes, std::string source, FbxDocument& out);

// Parses an ASCII FBX 7.x file into the same tree: "Name: values {children}"
// with values numbers, quoted strings, bare words and "*N { a: ... }" arrays
// of exactly N numbers. Errors name the line.
Status parse_fbx_ascii(std::string bytes, std::string source, FbxDocument& out);

// parse_fbx_binary or parse_fbx_ascii, by the magic.
Status parse_fbx(std::string bytes, std::string source, FbxDocument& out);

}  // namespace dfm::mesh
