#include <doctest/doctest.h>

#include <algorithm>
#include <optional>
#include <string>
#include <vector>

#include <glm/geometric.hpp>

#include "deform/mesh_model.hpp"
#include "environment/host_environment.hpp"
#include "mesh/load.hpp"
#include "mesh/model_cache.hpp"
#include "mesh/normals.hpp"
#include "pick/pick.hpp"
#include "roi/water_fill.hpp"
#include "support/real_models.hpp"

using namespace dfm;

namespace {

roi::WaterFill fill(const deform::MeshModel& m, std::uint32_t first, std::uint32_t last) {
    const roi::SurfaceView view{m.mesh.positions, m.mesh.triangles, &m.vertex_neighbors,
                                m.vertex_face_offsets, m.vertex_faces};
    roi::WaterFill out;
    const Status s = roi::water_fill(view, first, last, out);
    REQUIRE_MESSAGE(s.is_ok(), s.message());
    return out;
}

// A limb as a test names it, with what the paper's definition gives.
struct Limb {
    const char* model;
    const char* what;
    std::uint32_t first;
    std::uint32_t last;
    std::size_t vertices;
    std::size_t loops;
    bool bounded_by_last_loop;
    bool suspect;
};

void check_limb(const deform::MeshModel& model, const Limb& limb) {
    CAPTURE(limb.model);
    CAPTURE(limb.what);
    const roi::WaterFill w = fill(model, limb.first, limb.last);
    CHECK(w.vertices.size() == limb.vertices);
    CHECK(w.diagnosis.loops == limb.loops);
    CHECK(w.diagnosis.bounded_by_last_loop == limb.bounded_by_last_loop);
    CHECK(w.diagnosis.suspect == limb.suspect);
    CHECK(std::binary_search(w.vertices.begin(), w.vertices.end(), limb.first));
    CHECK_FALSE(std::binary_search(w.vertices.begin(), w.vertices.end(), limb.last));
    // Nothing in the region lies on or beyond the plane.
    const auto& p = model.mesh.positions;
    const glm::dvec3 n = glm::normalize(p[limb.last] - p[limb.first]);
    for (std::uint32_t v : w.vertices) CHECK(glm::dot(p[v] - p[limb.last], n) < 0.0);
}

}  // namespace

TEST_CASE("water_fill: the paper's cow limbs (issue 4)") {
    const deform::MeshModel cow = test::load_real_model("cow");
    for (const Limb& limb : {
             Limb{"cow", "lower front leg from the hoof", 771, 681, 138, 1, true, false},
             Limb{"cow", "hind leg", 901, 827, 82, 1, true, false},
             // The plane through 1959 cuts the tail and the rump: two loops.
             Limb{"cow", "tail tip to 1959", 2334, 1959, 684, 2, true, true},
         }) {
        check_limb(cow, limb);
    }
}

// Further limbs, their vertices found by looking at the geometry: a tip
// (extreme along an axis) and a vertex part way towards the body.
TEST_CASE("water_fill: more limbs of the paper's models") {
    const deform::MeshModel cow = test::load_real_model("cow");
    // 2334: the tail tip (lowest x); 964: up the tail, below its root.
    check_limb(cow, {"cow", "tail", 2334, 964, 131, 1, true, false});
    // One vertex further, 939 sits on the back: the plane cuts the body and
    // the fill takes more than half the cow.
    check_limb(cow, {"cow", "tail leaking into the body", 2334, 939, 1670, 1, true, true});

    const deform::MeshModel camel = test::load_real_model("camel");
    // 9067: the lowest vertex, a hoof; 3324: up the same leg, y = -0.306.
    check_limb(camel, {"camel", "leg", 9067, 3324, 664, 1, true, false});

    const deform::MeshModel dino = test::load_real_model("dino");
    // The dino stands along +z: 1706 (largest z) is the top of its head;
    // 1637, z = 1.0, on the long neck. The fill is the head and upper neck.
    check_limb(dino, {"dino", "head and neck", 1706, 1637, 1065, 1, true, false});
    // 1313 next to the top: the plane runs along the neck and cuts it twice.
    check_limb(dino, {"dino", "neck cut lengthwise", 1706, 1313, 1844, 2, true, true});

    // The selections of the shared scenarios (tests/scenarios/*.json).
    check_limb(camel, {"camel", "head (camel-head-turn)", 315, 1858, 740, 1, true, false});
    check_limb(dino, {"dino", "dino-tail-lift", 3528, 2619, 272, 1, true, false});

    const deform::MeshModel triceratops = test::load_real_model("triceratops");
    check_limb(triceratops,
               {"triceratops", "horn (triceratops-horn-rotate)", 2322, 2356, 46, 1, true, false});
    // 409: a brow horn's tip (largest x); 371: at the horn's base.
    check_limb(triceratops, {"triceratops", "horn", 409, 371, 32, 1, true, false});
}

// Clicks through a camera pick the vertices Water-Filling starts from: a
// camera looking at the hoof from outside puts vertex 771 at the image's
// centre, and the pick there returns 771.
TEST_CASE("water_fill: clicks on the cow pick the vertices the fill uses") {
    const deform::MeshModel cow = test::load_real_model("cow");
    std::vector<glm::dvec3> normals;
    mesh::compute_vertex_normals(cow.mesh, cow.mesh.positions, normals);
    pick::EmbreeScene scene;
    REQUIRE(pick::EmbreeScene::create(cow.mesh.positions, cow.mesh.triangles, scene).is_ok());
    for (const std::uint32_t v : {771u, 681u, 901u, 827u}) {
        CAPTURE(v);
        pick::Camera camera;
        camera.target = cow.mesh.positions[v];
        camera.eye = camera.target + 0.4 * glm::normalize(normals[v]);
        camera.up = std::abs(normals[v].y) > 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
        camera.fov_y_degrees = 30.0;
        camera.width = 640;
        camera.height = 480;
        const auto pixel = pick::project(camera, cow.mesh.positions[v]);
        REQUIRE(pixel.has_value());
        CHECK(glm::length(*pixel - glm::dvec2(320.0, 240.0)) < 1e-9);
        std::optional<pick::Hit> hit;
        REQUIRE(pick::pick_pixel(scene, camera, *pixel, hit).is_ok());
        REQUIRE(hit.has_value());
        CHECK(hit->vertex == v);
        const auto& t = cow.mesh.triangles[hit->face];
        CHECK(std::find(t.begin(), t.end(), v) != t.end());
        CHECK(glm::length(hit->point - cow.mesh.positions[v]) < 1e-6);
    }
}
