#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include <glm/mat4x4.hpp>

#include "json/json_reader.hpp"

// A small glTF 2.0 reader of the tests' own, apart from the SDK's, so that a
// test checks what Dualform wrote against an independent reading: the JSON
// (through the tools' JSON module), the buffers (GLB chunk, external file or
// data URI) and the bytes of an accessor. Every problem fails the test.
namespace dfm::test::gltf {

struct Asset {
    std::filesystem::path path;
    json::JsonValue doc;
    std::vector<std::string> buffers;  // the bytes of each buffer
};

Asset read_asset(const std::filesystem::path& path);

// The member `key` of object `v`; fails the test when absent.
const json::JsonValue& member(const json::JsonValue& v, std::string_view key);
// The integer member `key`, or `fallback` when absent.
std::size_t index_or(const json::JsonValue& v, std::string_view key, std::size_t fallback);

// The bytes of accessor `index`'s elements one after another, any byte
// stride taken out (sparse accessors are not read here).
std::string accessor_bytes(const Asset& asset, std::size_t index);

// The float components of accessor `index` (componentType FLOAT), widened.
std::vector<double> accessor_floats(const Asset& asset, std::size_t index);

// The index of the mesh named `name`; fails the test when there is none.
std::size_t mesh_index(const Asset& asset, std::string_view name);

// The world matrix of the (first) node that instances mesh `mesh`.
glm::dmat4 mesh_world_matrix(const Asset& asset, std::size_t mesh);

// The POSITION values of every primitive of mesh `mesh`, one after another.
std::vector<double> mesh_positions(const Asset& asset, std::size_t mesh);

// The triangles (three vertex indices each) of every primitive of mesh
// `mesh`, primitive k's indices offset by the vertices of those before it,
// as mesh_positions lists them.
std::vector<std::uint32_t> mesh_triangles(const Asset& asset, std::size_t mesh);

// Points (x0, y0, z0, x1, ...) moved by `m`.
std::vector<double> transformed(const glm::dmat4& m, const std::vector<double>& points);

}  // namespace dfm::test::gltf
