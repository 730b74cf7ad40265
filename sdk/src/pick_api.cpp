#include <cmath>
#include <optional>

#include "c_boundary.hpp"
#include "host_numbering.hpp"
#include "objects.hpp"
#include "pick/pick.hpp"
#include "pick_camera.hpp"

using namespace dfm;
using namespace dfm::sdk;

namespace dfm::sdk {

Status with_scene(MeshState& state, const std::function<Status(const pick::EmbreeScene&)>& use) {
    std::lock_guard<std::mutex> lock(state.scene_mutex);
    const deform::RestPoses::Pose current = state.current();
    const deform::MeshModel& model = *current;
    if (state.scene.empty()) {
        if (Status s = pick::EmbreeScene::create(model.mesh.positions, model.mesh.triangles,
                                                 state.scene, state.context->pick_thread_count);
            !s) {
            return s;
        }
    } else if (state.scene_model != current) {
        if (Status s = state.scene.refit(model.mesh.positions); !s) return s;
    }
    state.scene_model = current;
    return use(state.scene);
}

}  // namespace dfm::sdk

namespace {

void fill_hit(const MeshState& state, const std::optional<pick::Hit>& hit, dfm_hit* out) {
    *out = dfm_hit{};
    if (!hit) return;
    const HostNumbering numbering(state, 0);
    out->hit = true;
    out->face = numbering.to_host_face(hit->face);
    out->vertex = numbering.to_host(hit->vertex);
    for (int c = 0; c < 3; ++c) out->point[c] = hit->point[c];
    out->distance = hit->distance;
    out->barycentric[0] = hit->u;
    out->barycentric[1] = hit->v;
    out->barycentric[2] = hit->w;
}

}  // namespace

extern "C" DFM_API dfm_result dfm_mesh_pick(dfm_mesh* mesh, const dfm_camera* camera, double x,
                                            double y, dfm_hit* out) {
    constexpr const char* fn = "dfm_mesh_pick";
    return guarded(fn, [&] {
        if (out == nullptr) return report(fn, DFM_ERROR_INVALID_ARGUMENT, "out is NULL");
        *out = dfm_hit{};
        MeshObject* m = resolve_mesh(mesh);
        if (m == nullptr) return bad_handle(fn, "mesh", mesh);
        if (camera == nullptr) return report(fn, DFM_ERROR_INVALID_ARGUMENT, "camera is NULL");
        if (!std::isfinite(x) || !std::isfinite(y)) {
            return report(fn, DFM_ERROR_INVALID_ARGUMENT, "the pixel is not finite");
        }
        const pick::Camera c = to_camera(*camera);
        if (Status s = pick::check_camera(c); !s) return report(fn, s);
        std::optional<pick::Hit> hit;
        const Status s = with_scene(*m->state, [&](const pick::EmbreeScene& scene) {
            return pick::pick_pixel(scene, c, {x, y}, hit);
        });
        if (!s) return report(fn, s);
        fill_hit(*m->state, hit, out);
        return DFM_OK;
    });
}

extern "C" DFM_API dfm_result dfm_mesh_pick_ray(dfm_mesh* mesh, const double origin[3],
                                                const double direction[3], dfm_hit* out) {
    constexpr const char* fn = "dfm_mesh_pick_ray";
    return guarded(fn, [&] {
        if (out == nullptr) return report(fn, DFM_ERROR_INVALID_ARGUMENT, "out is NULL");
        *out = dfm_hit{};
        MeshObject* m = resolve_mesh(mesh);
        if (m == nullptr) return bad_handle(fn, "mesh", mesh);
        if (origin == nullptr || direction == nullptr) {
            return report(fn, DFM_ERROR_INVALID_ARGUMENT, "origin or direction is NULL");
        }
        pick::Ray ray;
        ray.origin = {origin[0], origin[1], origin[2]};
        const glm::dvec3 d(direction[0], direction[1], direction[2]);
        const double length = std::sqrt(d.x * d.x + d.y * d.y + d.z * d.z);
        if (!(length > 0.0) || !std::isfinite(length) || !std::isfinite(ray.origin.x) ||
            !std::isfinite(ray.origin.y) || !std::isfinite(ray.origin.z)) {
            return report(fn, DFM_ERROR_INVALID_ARGUMENT,
                          "the ray needs a finite origin and a finite, non-zero direction");
        }
        ray.direction = d / length;
        std::optional<pick::Hit> hit;
        const Status s = with_scene(*m->state, [&](const pick::EmbreeScene& scene) {
            return pick::pick_ray(scene, ray, hit);
        });
        if (!s) return report(fn, s);
        fill_hit(*m->state, hit, out);
        return DFM_OK;
    });
}
