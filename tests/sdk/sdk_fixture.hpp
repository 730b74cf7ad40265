#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "dualform/dualform.h"
#include "mesh/mesh.hpp"

namespace dfm::test {

// A C API mesh from an engine mesh, through dfm_mesh_create with float
// positions (as most hosts hand them).
dfm_mesh* make_c_mesh(dfm_context* context, const mesh::Mesh& m);

// The limb edit's ROI (above y = 0.5) as a dfm_roi of `mesh`, and its tip
// (y >= 1.8), the handle group.
dfm_roi* make_limb_roi(const mesh::Mesh& shape, dfm_mesh* mesh, std::vector<std::uint32_t>& tip);

// The limb edit the session tests share: a capped cylinder along +y, the ROI
// above y = 0.5, one handle group at the tip (y >= 1.8).
struct LimbEdit {
    mesh::Mesh shape;
    dfm_context* context = nullptr;
    dfm_mesh* mesh = nullptr;
    dfm_roi* roi = nullptr;
    std::vector<std::uint32_t> tip;
    dfm_session* session = nullptr;

    explicit LimbEdit(int segments = 16, int rings = 20, dfm_solver_settings solver = {});
    ~LimbEdit();
    LimbEdit(const LimbEdit&) = delete;
    LimbEdit& operator=(const LimbEdit&) = delete;
};

// A translation as the column-major matrix dfm_session_set_group_transform takes.
void translation(double x, double y, double z, double out[16]);

// FNV-1a over the 64-bit words of `count` doubles (the frame checksum's
// definition in dualform.h), written here apart from the engine's so the
// test checks the frame against an independent sum.
std::uint64_t fnv1a_words(const double* values, std::size_t count);

// "CODE: message" of the last failure on this thread, for CHECK messages.
std::string last_error();

// Whether the last failure's message on this thread contains `text`.
bool message_has(const char* text);

}  // namespace dfm::test
