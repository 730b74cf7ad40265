#pragma once

// What the C API's opaque handles stand for. A handle is an index and a
// generation (handle_table.hpp), never an address, so a destroyed, foreign
// or recycled handle is refused with DFM_ERROR_INVALID_HANDLE instead of
// touching freed memory or another object.

#include <cstdint>
#include <memory>
#include <mutex>
#include <new>
#include <string>
#include <vector>

#include "core/buffer_pool.hpp"
#include "deform/edit.hpp"
#include "deform/mesh_model.hpp"
#include "deform/rest_poses.hpp"
#include "dualform/dualform.h"
#include "handle_table.hpp"
#include "jobs/scheduler.hpp"
#include "mesh/host_mesh.hpp"
#include "pick/embree_scene.hpp"

namespace dfm::sdk {

// The host's hooks, or malloc/free when both are NULL. allocate throws
// std::bad_alloc when the hook returns NULL.
void* host_allocate(const dfm_allocator& hooks, std::size_t size, std::size_t alignment);
void host_deallocate(const dfm_allocator& hooks, void* memory, std::size_t size);

struct ContextState {
    dfm_allocator allocator{};
    dfm_log_fn log = nullptr;
    void* log_user = nullptr;
    std::uint32_t pick_thread_count = 0;  // Embree's device; 0: Embree's default
    std::string models_directory;         // empty: model:NAME is not found
    std::string reference_folder;         // empty: references only in a file's own folder
    dfm_job_system job_system{};          // DFM_WORK_JOB_SYSTEM: where jobs go
    // While any context state lives, large buffers that sessions free are
    // kept for the next set-up (buffer_pool.hpp, one pool per process).
    buffer_pool::Hold keeps_buffers;
    // Runs the sessions' work; lives as long as any object of the context.
    std::unique_ptr<jobs::Scheduler> scheduler;

    void* allocate(std::size_t size, std::size_t alignment) const {
        return host_allocate(allocator, size, alignment);
    }
    void deallocate(void* memory, std::size_t size) const {
        host_deallocate(allocator, memory, size);
    }
    void emit(dfm_log_level level, dfm_log_id id, const std::string& message) const;
};

// A standard allocator over the host's hooks, held by value so that a
// shared_ptr's control block can outlive the context it came from.
template <class T>
struct HostAllocator {
    using value_type = T;
    dfm_allocator hooks;
    explicit HostAllocator(const dfm_allocator& h) : hooks(h) {}
    template <class U>
    HostAllocator(const HostAllocator<U>& other) : hooks(other.hooks) {}
    T* allocate(std::size_t n) {
        return static_cast<T*>(host_allocate(hooks, n * sizeof(T), alignof(T)));
    }
    void deallocate(T* p, std::size_t n) { host_deallocate(hooks, p, n * sizeof(T)); }
    template <class U>
    bool operator==(const HostAllocator<U>& other) const {
        return hooks.alloc == other.hooks.alloc && hooks.free == other.hooks.free &&
               hooks.user == other.hooks.user;
    }
};

// What a mesh handle stands for: its rest poses (bakes push, undo and redo
// move between), the host's numbering and the pick scene.
struct MeshState {
    MeshState(std::shared_ptr<const ContextState> context, mesh::HostMesh host,
              deform::RestPoses::Pose first)
        : context(std::move(context)),
          host(std::move(host)),
          poses(std::move(first), this->host.skin, [hooks = this->context->allocator] {
              return std::allocate_shared<deform::MeshModel>(
                  HostAllocator<deform::MeshModel>(hooks));
          }) {}

    std::shared_ptr<const ContextState> context;
    // The host's numbering, the glTF asset and the skin, fixed for the
    // mesh's life (bakes move vertices, never renumber them); see
    // host_numbering.hpp.
    mesh::HostMesh host;
    // In bind space, shown at the skin's pose when one is set.
    deform::RestPoses poses;
    // Built on the first pick for `scene_model`, refit after a bake or
    // undo; under scene_mutex.
    std::mutex scene_mutex;
    pick::EmbreeScene scene;
    deform::RestPoses::Pose scene_model;

    deform::RestPoses::Pose current() const { return poses.current(); }
};

// The objects behind the C API's handles. Each names its handle type and
// kind; handles map to objects through handle_table.hpp.
struct ContextObject {
    using Handle = dfm_context;
    static constexpr Kind kind = Kind::context;
    std::shared_ptr<const ContextState> state;

    // The host lets go of the context: with its job system or stepping,
    // the host's part of the work ends here (jobs::Scheduler::close); the
    // pool's threads go on for the objects that outlive the handle.
    ~ContextObject() {
        if (state->scheduler->mode() != jobs::Mode::pool) state->scheduler->close();
    }
};

struct MeshObject {
    using Handle = dfm_mesh;
    static constexpr Kind kind = Kind::mesh;
    std::shared_ptr<MeshState> state;
};

struct RoiObject {
    using Handle = dfm_roi;
    static constexpr Kind kind = Kind::roi;
    std::shared_ptr<MeshState> mesh;
    std::vector<std::uint32_t> vertices;  // ascending
};

struct SessionObject {
    using Handle = dfm_session;
    static constexpr Kind kind = Kind::session;
    std::shared_ptr<MeshState> mesh;
    // The held frame's lists in the host's numbering, on a mesh with split
    // copies (dfm_session_acquire_frame).
    std::vector<std::uint32_t> held_roi_vertices;
    std::vector<std::uint32_t> held_normal_vertices;
    std::unique_ptr<deform::Edit> edit;  // last: stopped before the rest goes
};

static_assert(sizeof(void*) == sizeof(std::uint64_t), "handles are 64-bit values");

template <class Handle>
std::uint64_t handle_bits(const Handle* handle) {
    return reinterpret_cast<std::uintptr_t>(handle);
}

template <class T>
T* resolve(const typename T::Handle* handle) {
    return static_cast<T*>(handles(T::kind).find(handle_bits(handle)));
}

// The live object behind a handle, or null for NULL, a destroyed handle or
// one of another kind.
inline ContextObject* resolve_context(const dfm_context* h) {
    return resolve<ContextObject>(h);
}
inline MeshObject* resolve_mesh(const dfm_mesh* h) {
    return resolve<MeshObject>(h);
}
inline RoiObject* resolve_roi(const dfm_roi* h) {
    return resolve<RoiObject>(h);
}
inline SessionObject* resolve_session(const dfm_session* h) {
    return resolve<SessionObject>(h);
}

inline std::shared_ptr<const ContextState> context_of(const ContextObject& c) {
    return c.state;
}
inline std::shared_ptr<const ContextState> context_of(const MeshObject& m) {
    return m.state->context;
}
inline std::shared_ptr<const ContextState> context_of(const RoiObject& r) {
    return r.mesh->context;
}
inline std::shared_ptr<const ContextState> context_of(const SessionObject& s) {
    return s.mesh->context;
}

// Creates an object in memory from the context's allocator and returns its
// new handle.
template <class T, class... Args>
typename T::Handle* host_new(const ContextState& context, Args&&... args) {
    void* memory = context.allocate(sizeof(T), alignof(T));
    T* object = nullptr;
    try {
        object = new (memory) T{std::forward<Args>(args)...};
        return reinterpret_cast<typename T::Handle*>(
            static_cast<std::uintptr_t>(handles(T::kind).insert(object)));
    } catch (...) {
        if (object != nullptr) object->~T();
        context.deallocate(memory, sizeof(T));
        throw;
    }
}

// Retires the handle and frees its object; a handle that is not live is
// left alone.
template <class T>
void host_delete(const typename T::Handle* handle) {
    T* object = static_cast<T*>(handles(T::kind).erase(handle_bits(handle)));
    if (object == nullptr) return;
    // The object may hold the last reference to the context; keep it alive
    // until its memory is returned.
    std::shared_ptr<const ContextState> context = context_of(*object);
    object->~T();
    context->deallocate(object, sizeof(T));
}

}  // namespace dfm::sdk
