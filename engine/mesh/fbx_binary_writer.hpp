#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "mesh/fbx_document.hpp"

// Writing binary FBX: a tree of nodes whose properties are kept as encoded
// bytes, so that a node copied from a file is written back exactly as it
// was read (only the node headers' offsets, which say where things lie in
// the file, change).
namespace dfm::mesh {

struct FbxOutNode {
    std::string name;
    std::string properties;  // each property's type code and value, as the file stores them
    std::uint32_t property_count = 0;
    std::vector<FbxOutNode> children;
    bool null_record = false;  // close the nested list with a null record even without children

    static FbxOutNode named(std::string_view name);
    FbxOutNode& add_int32(std::int32_t v);
    FbxOutNode& add_int64(std::int64_t v);
    FbxOutNode& add_double(double v);
    FbxOutNode& add_string(std::string_view v);
    // Arrays of more than 128 bytes are deflated, as FBX's own writers do.
    FbxOutNode& add_int32_array(std::span<const std::int32_t> v);
    FbxOutNode& add_double_array(std::span<const double> v);
    // A child with that name, appended; returns it (valid until the next
    // change to this node's children).
    FbxOutNode& add_child(std::string_view child_name);
};

// The whole tree of a binary document, each node's properties copied byte
// for byte.
std::vector<FbxOutNode> fbx_out_tree(const FbxDocument& doc);
FbxOutNode fbx_out_node(const FbxDocument& doc, std::uint32_t node);

// Binary FBX of version `version` (7500 and later: 64-bit node headers):
// the magic, the nodes, the top-level null record and `doc`'s footer (its
// alignment padding recomputed, its version set, where it has the layout FBX
// writers give it; else copied as it is).
std::string encode_fbx(const FbxDocument& doc, const std::vector<FbxOutNode>& roots,
                       std::uint32_t version);

}  // namespace dfm::mesh
