#pragma once

#include <filesystem>
#include <string>

#include "core/status.hpp"
#include "mesh/load.hpp"
#include "mesh/mesh.hpp"

namespace dfm::mesh {

enum class PlyEncoding { binary_little_endian, binary_big_endian, ascii };

struct WriteOptions {
    PlyEncoding ply_encoding = PlyEncoding::binary_little_endian;
    bool ply_double = true;    // double coordinates (exact); float when false
    bool obj_normals = false;  // area-weighted vertex normals as "vn", faces as v//vn
    // glTF from glTF only: keep the base positions and add the edit as a
    // morph target of this name (empty: write the new positions).
    std::string morph_target = {};
    // A JSON object's text recorded as the morph target's POSITION
    // accessor's extras (the pose of a corrective); empty: none.
    std::string morph_target_extras = {};
};

// Each writes the whole file into `out`; coordinates round-trip exactly
// (except float PLY).
void write_off(const Mesh& mesh, std::string& out);
void write_obj(const Mesh& mesh, const WriteOptions& options, std::string& out);
void write_ply(const Mesh& mesh, const WriteOptions& options, std::string& out);

// Writes `mesh` in the format its extension names. The file is written beside
// its final name and renamed over it only when complete, so a failure never
// leaves a half-written file or destroys an existing one.
// .gltf and .glb get a fresh, minimal asset (host_mesh.hpp writes a mesh
// back into the asset it came from).
Status save_mesh(const std::filesystem::path& path, const Mesh& mesh,
                 const WriteOptions& options = {});

// Writes `bytes` beside `path` and renames the file over it when complete.
Status write_file_atomically(const std::filesystem::path& path, const std::string& bytes);

}  // namespace dfm::mesh
