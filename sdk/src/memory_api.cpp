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
        const MeshState& state = *m->state;
        std::lock_guard<std::mutex> lock(state.mutex);
        const deform::MeshModel::Memory current = state.model->memory();
        out->rest_pose = current.mesh;
        out->adjacency = current.adjacency;
        out->model = current.dual;
        // Each pose once, whichever lists hold it.
        std::unordered_set<const deform::MeshModel*> counted{state.model.get()};
        for (const auto* poses : {&state.undo, &state.redo}) {
            for (const std::shared_ptr<const deform::MeshModel>& pose : *poses) {
                if (counted.insert(pose.get()).second) out->history += model_bytes(*pose);
            }
        }
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
        deform::SessionMemory engine;
        std::size_t staging = capacity_bytes(s->roi, s->groups, s->handle_vertices);
        for (const std::vector<std::uint32_t>& group : s->groups) staging += capacity_bytes(group);
        {
            std::lock_guard<std::mutex> lock(s->staging_mutex);
            engine = s->async->memory();
            staging += capacity_bytes(s->staged, s->handle_rest, s->group_offsets);
        }
        {
            std::lock_guard<std::mutex> lock(s->solving_mutex);
            staging += capacity_bytes(s->solving);
        }
        {
            std::lock_guard<std::mutex> lock(s->rest_normals_mutex);
            staging += capacity_bytes(s->rest_normals);
        }
        out->factor = engine.factor;
        out->normal_matrix = engine.system;
        out->iteration = engine.iteration;
        out->frames = engine.frames;
        out->staging = engine.staging + staging;
        out->total = out->factor + out->normal_matrix + out->iteration + out->frames + out->staging;
        return DFM_OK;
    });
}
