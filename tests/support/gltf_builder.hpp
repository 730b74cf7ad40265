#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "mesh/mesh.hpp"

// glTF 2.0 documents written in test code: one binary buffer, buffer views
// and accessors appended one by one, and the rest of the document (meshes,
// nodes, materials, animations) given as JSON text.
namespace dfm::test {

class GltfBuilder {
public:
    // A buffer view over `bytes` (4-byte aligned); `stride` 0: packed.
    int view(const std::string& bytes, int stride = 0);
    template <class T>
    int view_of(const std::vector<T>& values, int stride = 0) {
        return view(
            std::string(reinterpret_cast<const char*>(values.data()), values.size() * sizeof(T)),
            stride);
    }
    // An accessor; `extra` is more JSON members (",\"normalized\":true").
    int accessor(int view, int component_type, std::size_t count, const std::string& type,
                 std::size_t byte_offset = 0, const std::string& extra = "");
    // A float VEC3 POSITION accessor with its bounds.
    int positions(const std::vector<float>& xyz);
    int floats(const std::vector<float>& values, const std::string& type);
    int indices_u8(const std::vector<std::uint8_t>& v);
    int indices_u16(const std::vector<std::uint16_t>& v);
    int indices_u32(const std::vector<std::uint32_t>& v);

    // Top-level members besides asset, buffers, bufferViews and accessors,
    // as JSON text without braces: "\"meshes\":[...],\"nodes\":[...]".
    std::string members;

    std::string json(const std::string& buffer_uri) const;  // "" : no uri (GLB)
    std::string gltf_embedded() const;
    std::string glb() const;
    // FILE.gltf and FILE.bin beside it.
    void write_external(const std::filesystem::path& gltf, const std::string& bin_name) const;

    const std::string& bin() const { return bin_; }

private:
    std::string bin_;
    std::vector<std::string> views_, accessors_;
};

std::vector<float> float_positions(const mesh::Mesh& m);

// Gives every face for which `split(face)` holds its own copies of its
// corners (as a renderer splits for UV, normal or material seams); a
// vertex's first face keeps the original.
mesh::Mesh split_corners(const mesh::Mesh& m, bool (*split)(std::size_t face));

// The same mesh with float-rounded positions (what a glTF holds).
mesh::Mesh rounded_to_float(const mesh::Mesh& m);

}  // namespace dfm::test
