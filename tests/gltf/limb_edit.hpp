#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <vector>

#include "dualform/dualform.h"

// One limb edit through the C API, as a host makes it: Water-Filling from
// two vertices, a ball of handle vertices moved by a translation, solved to
// a tight tolerance so that two meshes of the same surface agree to rounding
// whatever their vertex order.
namespace dfm::test::gltf {

struct ContextDeleter {
    void operator()(dfm_context* c) const { dfm_context_destroy(c); }
};
struct MeshDeleter {
    void operator()(dfm_mesh* m) const { dfm_mesh_destroy(m); }
};
using ContextPtr = std::unique_ptr<dfm_context, ContextDeleter>;
using MeshPtr = std::unique_ptr<dfm_mesh, MeshDeleter>;

ContextPtr make_context();

// dfm_mesh_load; fails the test with the library's message.
MeshPtr load_mesh(dfm_context* context, const std::filesystem::path& path);

// The rest positions (x0, y0, z0, x1, ...), in double.
std::vector<double> rest_positions(const dfm_mesh* mesh);

double diagonal(const dfm_mesh* mesh);

struct LimbEdit {
    std::uint32_t first = 0;   // Water-Filling from here
    std::uint32_t last = 0;    // to the plane through here
    std::uint32_t handle = 0;  // the handle: the ROI's vertices within
    double handle_radius = 0;  // this many diagonals of `handle`
    double translate[3] = {};  // moved by this
};

struct EditOutcome {
    std::vector<std::uint32_t> roi;
    std::vector<std::uint32_t> handles;
    std::vector<double> positions;  // the solved frame, every vertex
};

// Makes the edit and solves it; with `bake`, bakes it into the rest pose.
EditOutcome edit_limb(dfm_mesh* mesh, const LimbEdit& edit, bool bake);

}  // namespace dfm::test::gltf
