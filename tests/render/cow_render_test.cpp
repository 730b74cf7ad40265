#include <doctest/doctest.h>

#include <memory>
#include <vector>

#include <glm/geometric.hpp>

#include "deform/deform_session.hpp"
#include "deform/mesh_model.hpp"
#include "environment/host_environment.hpp"
#include "mesh/load.hpp"
#include "mesh/model_cache.hpp"
#include "render/render_helpers.hpp"
#include "support/test_files.hpp"

using namespace dfm;
using namespace dfm::test;

namespace {

// The paper's cow; its front leg around vertex 771 (tools/demo's edit).
constexpr std::uint32_t leg_vertex = 771;

mesh::Mesh load_cow() {
    std::filesystem::path path;
    const Status resolved = mesh::resolve_mesh_spec(
        "model:cow", ".", dfm::tools::models_folder_from_environment(), path);
    REQUIRE_MESSAGE(resolved.is_ok(), resolved.message());
    mesh::Mesh cow;
    const Status loaded = mesh::load_mesh(path, cow);
    REQUIRE_MESSAGE(loaded.is_ok(), loaded.message());
    return cow;
}

// Vertices within `fraction` of the diagonal of `center`.
std::vector<std::uint8_t> ball(const mesh::Mesh& m, std::uint32_t center, double fraction) {
    const double r = fraction * mesh::compute_bounds(m.positions).diagonal();
    std::vector<std::uint8_t> in(m.vertex_count(), 0);
    for (std::size_t v = 0; v < m.vertex_count(); ++v) {
        in[v] = glm::distance(m.positions[v], m.positions[center]) < r ? 1 : 0;
    }
    return in;
}

std::vector<std::uint32_t> indices_of(const std::vector<std::uint8_t>& in) {
    std::vector<std::uint32_t> out;
    for (std::uint32_t v = 0; v < in.size(); ++v) {
        if (in[v]) out.push_back(v);
    }
    return out;
}

dfm_camera cow_camera(const mesh::Mesh& cow) {
    dfm_camera camera = {};
    const dfm_vec3_input positions = positions_of(cow);
    REQUIRE(dfm_vk_framing_camera(&positions, 320, 240, &camera) == DFM_OK);
    return camera;
}

}  // namespace

TEST_CASE("render: the cow covers a plausible share of the picture") {
    const mesh::Mesh cow = load_cow();
    HeadlessScene scene(cow);
    const std::vector<std::uint8_t> rgba = scene.render(cow_camera(cow));
    const double share =
        1.0 - static_cast<double>(count_pixels(rgba, is_background)) / (rgba.size() / 4);
    CHECK(share > 0.10);
    CHECK(share < 0.80);
    CHECK(count_pixels(rgba, is_red) == 0);
    CHECK(scene.messages() == 0);
}

TEST_CASE("render: red pixels appear where the ROI projects, and nowhere else") {
    const mesh::Mesh cow = load_cow();
    HeadlessScene scene(cow);
    const dfm_camera camera = cow_camera(cow);
    const std::vector<std::uint8_t> roi = ball(cow, leg_vertex, 0.12);
    std::vector<std::uint8_t> marks(roi.begin(), roi.end());
    REQUIRE(dfm_vk_renderer_set_marks(scene.renderer(), marks.data(), marks.size()) == DFM_OK);
    const std::vector<std::uint8_t> rgba = scene.render(camera);
    const std::vector<std::uint8_t> mask =
        projected_mask(cow, cow.positions, roi, to_pick_camera(camera), 1);

    std::size_t red = 0, outside = 0;
    for (std::size_t i = 0; i < mask.size(); ++i) {
        if (!is_red(rgba, i)) continue;
        ++red;
        if (!mask[i]) ++outside;
    }
    CHECK(red > 100);
    CHECK(outside == 0);
    CHECK(scene.messages() == 0);
}

TEST_CASE("render: a deformation changes the picture only around the ROI") {
    const mesh::Mesh cow = load_cow();
    const deform::MeshModel model = deform::build_mesh_model(cow);
    const std::vector<std::uint32_t> roi = indices_of(ball(cow, leg_vertex, 0.12));
    const std::vector<std::vector<std::uint32_t>> handles = {
        indices_of(ball(cow, leg_vertex, 0.03))};
    std::unique_ptr<deform::DeformSession> session;
    REQUIRE(deform::DeformSession::create(model, roi, handles, {}, session).is_ok());
    std::vector<glm::dvec3> targets;
    for (std::uint32_t v : handles[0]) {
        targets.push_back(cow.positions[v] + glm::dvec3(0.05 * model.diagonal, 0.0, 0.0));
    }
    REQUIRE(session->set_targets(targets).is_ok());
    deform::SolveReport report;
    REQUIRE(session->solve(report).is_ok());
    const std::vector<glm::dvec3> deformed(session->positions().begin(),
                                           session->positions().end());

    HeadlessScene scene(cow);
    const dfm_camera camera = cow_camera(cow);
    const std::vector<std::uint8_t> before = scene.render(camera);
    const dfm_vec3_input moved = positions_of(deformed);
    REQUIRE(dfm_vk_renderer_update_positions(scene.renderer(), &moved) == DFM_OK);
    const std::vector<std::uint8_t> after = scene.render(camera);

    // Moved vertices and their neighbours (whose smooth normals change).
    std::vector<std::uint8_t> touched(cow.vertex_count(), 0);
    for (const mesh::Triangle& t : cow.triangles) {
        bool moves = false;
        for (std::uint32_t v : t) moves = moves || deformed[v] != cow.positions[v];
        if (moves) {
            for (std::uint32_t v : t) touched[v] = 1;
        }
    }
    const pick::Camera view = to_pick_camera(camera);
    const std::vector<std::uint8_t> rest_mask =
        projected_mask(cow, cow.positions, touched, view, 1);
    const std::vector<std::uint8_t> moved_mask = projected_mask(cow, deformed, touched, view, 1);
    std::size_t changed = 0, outside = 0;
    for (std::size_t i = 0; i < rest_mask.size(); ++i) {
        if (std::equal(&before[4 * i], &before[4 * i + 4], &after[4 * i])) continue;
        ++changed;
        if (!rest_mask[i] && !moved_mask[i]) ++outside;
    }
    CHECK(changed > 50);
    CHECK(outside == 0);
    CHECK(scene.messages() == 0);
}
