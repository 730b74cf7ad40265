#include "sdk/sdk_fixture.hpp"

#include <doctest/doctest.h>

#include <cstring>

#include "support/procedural_meshes.hpp"

namespace dfm::test {

dfm_mesh* make_c_mesh(dfm_context* context, const mesh::Mesh& m) {
    std::vector<float> xyz;
    for (const glm::dvec3& p : m.positions) {
        xyz.insert(xyz.end(),
                   {static_cast<float>(p.x), static_cast<float>(p.y), static_cast<float>(p.z)});
    }
    dfm_mesh_desc desc = {};
    desc.positions.data = xyz.data();
    desc.positions.count = m.vertex_count();
    desc.indices = m.triangles.front().data();
    desc.triangle_count = m.face_count();
    dfm_mesh* out = nullptr;
    REQUIRE_MESSAGE(dfm_mesh_create(context, &desc, &out) == DFM_OK, last_error());
    return out;
}

dfm_roi* make_limb_roi(const mesh::Mesh& shape, dfm_mesh* mesh, std::vector<std::uint32_t>& tip) {
    std::vector<std::uint32_t> region;
    for (std::uint32_t v = 0; v < shape.vertex_count(); ++v) {
        if (shape.positions[v].y > 0.5) region.push_back(v);
        if (shape.positions[v].y >= 1.8) tip.push_back(v);
    }
    dfm_roi* roi = nullptr;
    REQUIRE_MESSAGE(dfm_roi_from_vertices(mesh, region.data(), region.size(), &roi) == DFM_OK,
                    last_error());
    return roi;
}

LimbEdit::LimbEdit(int segments, int rings, dfm_solver_settings solver)
    : shape(make_limb(segments, rings, 0.2, 2.0)) {
    REQUIRE(dfm_context_create(nullptr, &context) == DFM_OK);
    mesh = make_c_mesh(context, shape);
    roi = make_limb_roi(shape, mesh, tip);
    const dfm_handle_group group = {tip.data(), tip.size()};
    dfm_session_desc desc = {};
    desc.roi = roi;
    desc.groups = &group;
    desc.group_count = 1;
    desc.solver = solver;
    REQUIRE_MESSAGE(dfm_session_create(mesh, &desc, &session) == DFM_OK, last_error());
}

LimbEdit::~LimbEdit() {
    dfm_session_destroy(session);
    dfm_roi_destroy(roi);
    dfm_mesh_destroy(mesh);
    dfm_context_destroy(context);
}

void translation(double x, double y, double z, double out[16]) {
    for (int i = 0; i < 16; ++i) out[i] = (i % 5 == 0) ? 1.0 : 0.0;
    out[12] = x;
    out[13] = y;
    out[14] = z;
}

std::uint64_t fnv1a_words(const double* values, std::size_t count) {
    std::uint64_t hash = 0xcbf29ce484222325ull;
    for (std::size_t i = 0; i < count; ++i) {
        std::uint64_t word = 0;
        std::memcpy(&word, values + i, sizeof word);
        hash ^= word;
        hash *= 0x100000001b3ull;
    }
    return hash;
}

std::string last_error() {
    std::string s = dfm_result_name(dfm_last_error_code());
    s += ": ";
    s += dfm_last_error_message();
    return s;
}

bool message_has(const char* text) {
    return std::string(dfm_last_error_message()).find(text) != std::string::npos;
}

}  // namespace dfm::test
