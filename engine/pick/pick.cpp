#include "pick/pick.hpp"

#include <cmath>

#include <glm/geometric.hpp>

namespace dfm::pick {

namespace {

// Möller–Trumbore against the face's plane: fills t, u, v unless the ray
// runs parallel to the plane or the face is degenerate.
bool exact_intersection(const Ray& ray, glm::dvec3 p0, glm::dvec3 p1, glm::dvec3 p2, Hit& hit) {
    const glm::dvec3 e1 = p1 - p0;
    const glm::dvec3 e2 = p2 - p0;
    const glm::dvec3 pv = glm::cross(ray.direction, e2);
    const double det = glm::dot(e1, pv);
    const double scale = glm::length(e1) * glm::length(e2);
    if (!(std::abs(det) > 1e-14 * scale)) return false;
    const glm::dvec3 tv = ray.origin - p0;
    const glm::dvec3 qv = glm::cross(tv, e1);
    hit.u = glm::dot(tv, pv) / det;
    hit.v = glm::dot(ray.direction, qv) / det;
    hit.distance = glm::dot(e2, qv) / det;
    return std::isfinite(hit.u) && std::isfinite(hit.v) && std::isfinite(hit.distance);
}

}  // namespace

Status pick_ray(const EmbreeScene& scene, const Ray& ray, std::optional<Hit>& out) {
    out.reset();
    if (scene.empty()) return Status(Errc::invalid_argument, "pick: the scene is empty");
    const double length = glm::length(ray.direction);
    if (!std::isfinite(length) || !(length > 0.0) || !std::isfinite(glm::length(ray.origin))) {
        return Status(Errc::invalid_argument,
                      "pick: the ray needs a finite origin and a finite, non-zero direction");
    }
    const Ray unit{ray.origin, ray.direction / length};
    SceneHit found;
    if (!scene.intersect(unit, found)) return Status::ok();

    const mesh::Triangle& t = scene.triangles()[found.face];
    const auto positions = scene.positions();
    const glm::dvec3 p[3] = {positions[t[0]], positions[t[1]], positions[t[2]]};
    Hit hit;
    hit.face = found.face;
    if (!exact_intersection(unit, p[0], p[1], p[2], hit)) {
        hit.distance = found.distance;
        hit.u = found.u;
        hit.v = found.v;
    }
    hit.w = 1.0 - hit.u - hit.v;
    hit.point = unit.origin + hit.distance * unit.direction;
    // Ties go to the face's earlier vertex, so the answer is deterministic.
    int nearest = 0;
    for (int k = 1; k < 3; ++k) {
        if (glm::length(p[k] - hit.point) < glm::length(p[nearest] - hit.point)) nearest = k;
    }
    hit.vertex = t[static_cast<std::size_t>(nearest)];
    out = hit;
    return Status::ok();
}

Status pick_pixel(const EmbreeScene& scene, const Camera& camera, glm::dvec2 pixel,
                  std::optional<Hit>& out) {
    out.reset();
    if (Status s = check_camera(camera); !s) return s;
    if (!std::isfinite(pixel.x) || !std::isfinite(pixel.y)) {
        return Status(Errc::invalid_argument, "pick: the pixel must be finite");
    }
    return pick_ray(scene, pixel_ray(camera, pixel), out);
}

}  // namespace dfm::pick
