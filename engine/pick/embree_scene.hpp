#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

#include "core/status.hpp"
#include "mesh/mesh.hpp"
#include "pick/camera.hpp"

namespace dfm::pick {

// Embree's nearest hit of a ray: the face and Embree's single-precision
// distance and barycentrics (the hit is (1-u-v)·p0 + u·p1 + v·p2).
struct SceneHit {
    std::uint32_t face = 0;
    double distance = 0.0;
    double u = 0.0;
    double v = 0.0;
};

// One Embree device and scene for one triangle mesh. Embree traces in
// single precision, so the scene also keeps the mesh's double positions and
// triangles, against which a pick is finished exactly. Errors Embree reports
// (through its error callback) come back as Status; nothing aborts.
// Movable, not copyable. Intersecting is thread-safe between refits; refit
// is not safe while another thread intersects.
class EmbreeScene {
public:
    EmbreeScene();
    ~EmbreeScene();
    EmbreeScene(EmbreeScene&&) noexcept;
    EmbreeScene& operator=(EmbreeScene&&) noexcept;
    EmbreeScene(const EmbreeScene&) = delete;
    EmbreeScene& operator=(const EmbreeScene&) = delete;

    // Builds the scene. Fails (naming the vertex or face) on a non-finite
    // position or an out-of-range index, and on any Embree error; `out` is
    // then empty. `thread_count` is the Embree device's: 0 lets Embree start
    // one thread per hardware thread, 1 builds on the calling thread alone.
    static Status create(std::span<const glm::dvec3> positions,
                         std::span<const mesh::Triangle> triangles, EmbreeScene& out,
                         unsigned thread_count = 0);

    // Moves the vertices (same count, same triangles) and refits the BVH
    // instead of rebuilding it, so picks hit the deformed surface. On
    // failure the scene keeps its previous positions.
    Status refit(std::span<const glm::dvec3> positions);

    bool empty() const { return impl_ == nullptr; }
    std::span<const glm::dvec3> positions() const;
    std::span<const mesh::Triangle> triangles() const;

    // Embree's nearest hit along the ray beyond distance 0; false on a miss
    // or an empty scene.
    bool intersect(const Ray& ray, SceneHit& out) const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace dfm::pick
