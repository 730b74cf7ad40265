#pragma once

#include <filesystem>
#include <vector>

#include "mesh/mesh.hpp"

namespace dfm::test {

// Writes `m` into `dir` as OBJ with v/vt/vn corners, OBJ with negative
// (relative) indices, OBJ with normals, ascii PLY, and binary PLY of both
// byte orders; returns the paths.
std::vector<std::filesystem::path> write_model_variants(const mesh::Mesh& m,
                                                        const std::filesystem::path& dir);

}  // namespace dfm::test
