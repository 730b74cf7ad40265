#pragma once

#include <cstdint>
#include <optional>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "core/status.hpp"
#include "pick/camera.hpp"
#include "pick/embree_scene.hpp"

namespace dfm::pick {

// Where a ray meets the surface. Barycentrics follow Embree's convention,
// printed by `dualform pick` as "barycentric": [u, v, w]: with the face's
// vertices (p0, p1, p2) in the mesh's order, the point is
// w·p0 + u·p1 + v·p2 and w = 1 - u - v.
struct Hit {
    std::uint32_t face = 0;
    std::uint32_t vertex = 0;  // the face's vertex nearest to the point
    glm::dvec3 point{0.0};
    double distance = 0.0;  // along the ray, from its origin
    double u = 0.0;
    double v = 0.0;
    double w = 0.0;
};

// The nearest hit of the ray, or nothing on a miss. Embree finds the face in
// single precision; the point, distance and barycentrics are then the exact
// double-precision intersection of the ray with that face's plane (Embree's
// values where the face is degenerate or parallel to the ray). Fails on an
// empty scene or a ray with a non-finite or zero direction.
Status pick_ray(const EmbreeScene& scene, const Ray& ray, std::optional<Hit>& out);

// The same for the ray through a pixel of the camera (see pixel_ray); also
// fails when the camera cannot make rays.
Status pick_pixel(const EmbreeScene& scene, const Camera& camera, glm::dvec2 pixel,
                  std::optional<Hit>& out);

}  // namespace dfm::pick
