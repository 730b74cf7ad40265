#include <doctest/doctest.h>

#include <cmath>
#include <limits>
#include <optional>

#include <glm/geometric.hpp>

#include "pick/pick.hpp"
#include "support/procedural_meshes.hpp"

using namespace dfm;
using namespace dfm::pick;

namespace {

// Looks at the unit sphere from +z; the sphere fills the middle of the image.
Camera sphere_camera() {
    Camera c;
    c.eye = {0.3, 0.2, 3.0};
    c.target = {0.0, 0.0, 0.0};
    c.up = {0.0, 1.0, 0.0};
    c.fov_y_degrees = 45.0;
    c.width = 200;
    c.height = 150;
    return c;
}

EmbreeScene make_scene(const mesh::Mesh& m) {
    EmbreeScene scene;
    const Status s = EmbreeScene::create(m.positions, m.triangles, scene);
    REQUIRE_MESSAGE(s.is_ok(), s.message());
    return scene;
}

// The nearest intersection of the ray with any face, in double precision by
// brute force: what Embree's pick must agree with.
std::optional<double> brute_force_distance(const mesh::Mesh& m, const Ray& r) {
    std::optional<double> best;
    for (const mesh::Triangle& t : m.triangles) {
        const glm::dvec3 p0 = m.positions[t[0]];
        const glm::dvec3 e1 = m.positions[t[1]] - p0;
        const glm::dvec3 e2 = m.positions[t[2]] - p0;
        const glm::dvec3 n = glm::cross(e1, e2);
        const double denom = glm::dot(n, r.direction);
        if (denom == 0.0) continue;
        const double d = glm::dot(n, p0 - r.origin) / denom;
        if (d <= 0.0) continue;
        const glm::dvec3 q = r.origin + d * r.direction - p0;
        // Barycentrics of q by areas.
        const double a1 = glm::dot(glm::cross(q, e2), n) / glm::dot(n, n);
        const double a2 = glm::dot(glm::cross(e1, q), n) / glm::dot(n, n);
        if (a1 < -1e-12 || a2 < -1e-12 || a1 + a2 > 1.0 + 1e-12) continue;
        if (!best || d < *best) best = d;
    }
    return best;
}

}  // namespace

TEST_CASE("pick: icosphere hits are the exact ray-triangle intersections") {
    const mesh::Mesh sphere = test::make_icosphere(3);
    const EmbreeScene scene = make_scene(sphere);
    const Camera c = sphere_camera();
    int hits = 0;
    for (double y = 0.5; y < c.height; y += 7.0) {
        for (double x = 0.5; x < c.width; x += 7.0) {
            const Ray r = pixel_ray(c, {x, y});
            std::optional<Hit> hit;
            REQUIRE(pick_pixel(scene, c, {x, y}, hit).is_ok());
            const std::optional<double> expected = brute_force_distance(sphere, r);
            CAPTURE(x);
            CAPTURE(y);
            REQUIRE(hit.has_value() == expected.has_value());
            if (!hit) continue;
            ++hits;
            CHECK(std::abs(hit->distance - *expected) < 1e-9);
            CHECK(glm::length(hit->point - (r.origin + *expected * r.direction)) < 1e-9);
            // The convention printed as [u, v, w]: point = w·p0 + u·p1 + v·p2.
            const mesh::Triangle& t = sphere.triangles[hit->face];
            const glm::dvec3 from_weights = hit->w * sphere.positions[t[0]] +
                                            hit->u * sphere.positions[t[1]] +
                                            hit->v * sphere.positions[t[2]];
            CHECK(glm::length(from_weights - hit->point) < 1e-12);
            CHECK(hit->u + hit->v + hit->w == doctest::Approx(1.0));
            for (double b : {hit->u, hit->v, hit->w}) {
                CHECK(b >= -1e-6);
                CHECK(b <= 1.0 + 1e-6);
            }
            // The reported vertex is the face's vertex nearest the point.
            for (std::uint32_t v : t) {
                CHECK(glm::length(sphere.positions[hit->vertex] - hit->point) <=
                      glm::length(sphere.positions[v] - hit->point));
            }
        }
    }
    CHECK(hits > 100);
}

// A fine icosphere (level 8: faces about 0.004 across, so the flat faces lie
// at most about 4e-6 inside the sphere) against the analytic ray-sphere
// intersection. Along the ray the gap grows as 1/cos(incidence), so only
// rays meeting the sphere at most 60 degrees from its normal are held to the
// 1e-5 bound; grazing rays are not a fair test of the picker.
TEST_CASE("pick: fine icosphere hits within 1e-5 of the analytic sphere") {
    const mesh::Mesh sphere = test::make_icosphere(8);
    const EmbreeScene scene = make_scene(sphere);
    const Camera c = sphere_camera();
    int checked = 0;
    for (double y = 0.5; y < c.height; y += 5.0) {
        for (double x = 0.5; x < c.width; x += 5.0) {
            const Ray r = pixel_ray(c, {x, y});
            const double b = glm::dot(r.origin, r.direction);
            const double disc = b * b - (glm::dot(r.origin, r.origin) - 1.0);
            std::optional<Hit> hit;
            REQUIRE(pick_pixel(scene, c, {x, y}, hit).is_ok());
            if (disc < 0.0) {
                CHECK_FALSE(hit.has_value());
                continue;
            }
            const double t = -b - std::sqrt(disc);
            const glm::dvec3 analytic = r.origin + t * r.direction;
            if (glm::dot(glm::normalize(analytic), -r.direction) < 0.5) continue;
            CAPTURE(x);
            CAPTURE(y);
            REQUIRE(hit.has_value());
            CHECK(glm::length(hit->point - analytic) < 1e-5);
            CHECK(std::abs(hit->distance - t) < 1e-5);
            ++checked;
        }
    }
    CHECK(checked > 300);
}

TEST_CASE("pick: a ray that misses says so") {
    const mesh::Mesh sphere = test::make_icosphere(2);
    const EmbreeScene scene = make_scene(sphere);
    std::optional<Hit> hit;
    REQUIRE(pick_pixel(scene, sphere_camera(), {0.0, 0.0}, hit).is_ok());
    CHECK_FALSE(hit.has_value());
    // Pointing away from the sphere.
    REQUIRE(pick_ray(scene, Ray{{0.0, 0.0, 3.0}, {0.0, 0.0, 1.0}}, hit).is_ok());
    CHECK_FALSE(hit.has_value());
    // From inside, the sphere is hit from behind.
    REQUIRE(pick_ray(scene, Ray{{0.0, 0.0, 0.0}, {0.0, 0.0, 2.0}}, hit).is_ok());
    REQUIRE(hit.has_value());
    CHECK(hit->distance == doctest::Approx(1.0).epsilon(0.05));
}

TEST_CASE("pick: a bad ray or an empty scene is an error, not a miss") {
    const EmbreeScene empty;
    std::optional<Hit> hit;
    CHECK(pick_ray(empty, Ray{}, hit).code() == Errc::invalid_argument);
    const EmbreeScene scene = make_scene(test::make_icosphere(1));
    CHECK(pick_ray(scene, Ray{{0, 0, 3}, {0, 0, 0}}, hit).code() == Errc::invalid_argument);
    const double nan = std::numeric_limits<double>::quiet_NaN();
    CHECK(pick_ray(scene, Ray{{0, 0, 3}, {0, nan, -1}}, hit).code() == Errc::invalid_argument);
    Camera bad = sphere_camera();
    bad.width = 0;
    CHECK(pick_pixel(scene, bad, {1, 1}, hit).message().find("width") != std::string::npos);
}

TEST_CASE("pick: after a refit the same pixel hits the moved surface") {
    mesh::Mesh sphere = test::make_icosphere(3);
    EmbreeScene scene = make_scene(sphere);
    const Camera c = sphere_camera();
    const glm::dvec2 pixel{100.0, 75.0};
    std::optional<Hit> before;
    REQUIRE(pick_pixel(scene, c, pixel, before).is_ok());
    REQUIRE(before.has_value());

    // Pull the picked region towards the camera: every vertex within 0.5 of
    // the hit moves by 0.4 along +z, the rest stays.
    std::vector<glm::dvec3> moved = sphere.positions;
    for (glm::dvec3& p : moved) {
        if (glm::length(p - before->point) < 0.5) p.z += 0.4;
    }
    REQUIRE(scene.refit(moved).is_ok());
    std::optional<Hit> after;
    REQUIRE(pick_pixel(scene, c, pixel, after).is_ok());
    REQUIRE(after.has_value());
    CHECK(after->distance < before->distance - 0.3);
    const mesh::Triangle& t = sphere.triangles[after->face];
    const glm::dvec3 on_new =
        after->w * moved[t[0]] + after->u * moved[t[1]] + after->v * moved[t[2]];
    CHECK(glm::length(on_new - after->point) < 1e-12);
    sphere.positions = moved;
    const auto expected = brute_force_distance(sphere, pixel_ray(c, pixel));
    REQUIRE(expected.has_value());
    CHECK(std::abs(after->distance - *expected) < 1e-9);
    CHECK(scene.positions()[0] == moved[0]);
}

TEST_CASE("pick: refit and create reject what Embree cannot trace") {
    const mesh::Mesh sphere = test::make_icosphere(1);
    EmbreeScene scene = make_scene(sphere);
    std::vector<glm::dvec3> fewer(sphere.positions.begin(), sphere.positions.end() - 1);
    CHECK(scene.refit(fewer).message().find("positions") != std::string::npos);
    std::vector<glm::dvec3> nan_at_5 = sphere.positions;
    nan_at_5[5].y = std::numeric_limits<double>::quiet_NaN();
    const Status s = scene.refit(nan_at_5);
    CHECK(s.message().find("vertex 5") != std::string::npos);
    CHECK(scene.positions()[5] == sphere.positions[5]);  // unchanged on failure

    EmbreeScene bad;
    mesh::Mesh broken = sphere;
    broken.triangles[7][2] = 999;
    const Status b = EmbreeScene::create(broken.positions, broken.triangles, bad);
    CHECK(b.code() == Errc::out_of_range);
    CHECK(b.message().find("face 7") != std::string::npos);
    CHECK(bad.empty());
    CHECK(EmbreeScene::create(nan_at_5, sphere.triangles, bad).message().find("vertex 5") !=
          std::string::npos);
}
