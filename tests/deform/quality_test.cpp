// The quality figures count folds whatever the rigid motion: a crease turns
// the dihedral angles along it by about 180°, a smooth bend turns none by 90°.
#include <doctest/doctest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>

#include "deform/quality.hpp"
#include "support/procedural_meshes.hpp"

using namespace dfm;

namespace {

// A 12 × 4 grid (x from 0 to 12), every vertex in the ROI.
struct Grid {
    deform::MeshModel model = deform::build_mesh_model(test::make_grid(12, 4));
    std::vector<std::uint8_t> in_roi = std::vector<std::uint8_t>(model.mesh.vertex_count(), 1);

    deform::QualityReport measure(const std::vector<glm::dvec3>& deformed) const {
        return deform::measure_quality(model, deformed, in_roi, {}, {});
    }
};

}  // namespace

TEST_CASE("quality: a rigid motion creases no edge, where it may turn every face past 90°") {
    const Grid g;
    const glm::dmat4 motion = glm::rotate(glm::translate(glm::dmat4(1.0), glm::dvec3(3, -1, 2)),
                                          glm::radians(150.0), glm::dvec3(0.2, 1.0, 0.4));
    std::vector<glm::dvec3> moved;
    for (const glm::dvec3& p : g.model.mesh.positions)
        moved.emplace_back(motion * glm::dvec4(p, 1));
    const deform::QualityReport q = g.measure(moved);
    CHECK(q.creased_edges == 0);
    CHECK(q.flipped_faces == g.model.mesh.face_count());
}

TEST_CASE("quality: a smooth bend through 180° creases no edge") {
    const Grid g;
    // Rolled onto a cylinder: x from 0 to 12 becomes half a turn.
    std::vector<glm::dvec3> rolled;
    const double radius = 12.0 / std::numbers::pi;
    for (const glm::dvec3& p : g.model.mesh.positions) {
        const double a = p.x / radius;
        rolled.emplace_back(radius * std::sin(a), p.y, radius * (1.0 - std::cos(a)));
    }
    const deform::QualityReport q = g.measure(rolled);
    CHECK(q.creased_edges == 0);
    CHECK(q.flipped_faces > 0);  // half the grid faces the other way: a turn, not a fold
}

TEST_CASE("quality: a grid folded shut along a line creases the edges on that line") {
    const Grid g;
    // x > 6 reflected onto the other side of the plane x = 6 (lifted by a
    // little, so the two halves do not coincide): the four edges on x = 6
    // between interior faces turn by 180°.
    std::vector<glm::dvec3> folded;
    for (const glm::dvec3& p : g.model.mesh.positions) {
        folded.push_back(p.x > 6.0 ? glm::dvec3(12.0 - p.x, p.y, 0.01 * (p.x - 6.0)) : p);
    }
    const deform::QualityReport q = g.measure(folded);
    CHECK(q.creased_edges == 4);
}
