// dfm_mesh_get_memory and dfm_session_get_memory: bytes by part, from the
// capacities of the arrays each object holds.
#include <memory>
#include <mutex>
#include <unordered_set>

#include "c_boundary.hpp"
#include "core/memory_bytes.hpp"
#include "objects.hpp"

using namespace dfm;
using namespace dfm::sdk;

namespace {

std::size_t model_bytes(const deform::MeshModel& model) {
    const deform::MeshModel::Memory m = model.memory();
    return m.mesh + m.adjacency + m.dual;
}

}  // namespace

extern "C" DFM_API dfm_result dfm_mesh_get_memory(const dfm_mesh* mesh, dfm_mesh_memory* out) {
    constexpr const char* fn = "dfm_mesh_get_memory";
    return guarded(fn, [&] {
        if (out == nullptr) return report(fn, DFM_ERROR_INVALID_ARGUMENT, "out is NULL");
        *out = dfm_mesh_memory{};
        MeshObject* m = resolve_mesh(mesh);
        if (m == nullptr) return bad_handle(fn, "mesh", mesh);
        MeshState& state = *m->state;
        // Each pose once, whichever lists hold it; the current one first.
        std::unordered_set<const deform::MeshModel*> counted;
        state.poses.for_each([&](const deform::MeshModel& pose) {
            if (counted.empty()) {
                const deform::MeshModel::Memory current = pose.memory();
                out->rest_pose = current.mesh;
                out->adjacency = current.adjacency;
                out->model = current.dual;
            } else if (counted.count(&pose) == 0) {
                out->history += model_bytes(pose);
            }
            counted.insert(&pose);
        });
        std::lock_guard<std::mutex> lock(state.scene_mutex);
        if (!state.scene.empty()) {
            const std::size_t vertices = state.scene.positions().size();
            const std::size_t triangles = state.scene.triangles().size();
            // The copies the scene refits from, and Embree's float3 and uint3 buffers.
            out->pick_scene = vertices * (sizeof(glm::dvec3) + 3 * sizeof(float)) +
                              triangles * (sizeof(mesh::Triangle) + 3 * sizeof(std::uint32_t));
        }
        out->total = out->rest_pose + out->adjacency + out->model + out->history + out->pick_scene;
        return DFM_OK;
    });
}

extern "C" DFM_API dfm_result dfm_session_get_memory(dfm_session* session,
                                                     dfm_session_memory* out) {
    constexpr const char* fn = "dfm_session_get_memory";
    return guarded(fn, [&] {
        if (out == nullptr) return report(fn, DFM_ERROR_INVALID_ARGUMENT, "out is NULL");
        *out = dfm_session_memory{};
        SessionObject* s = resolve_session(session);
        if (s == nullptr) return bad_handle(fn, "session", session);
        const deform::SessionMemory engine = s->edit->memory();
        out->factor = engine.factor;
        out->normal_matrix = engine.system;
        out->iteration = engine.iteration;
        out->frames = engine.frames;
        out->staging = engine.staging;
        out->total = out->factor + out->normal_matrix + out->iteration + out->frames + out->staging;
        return DFM_OK;
    });
}
