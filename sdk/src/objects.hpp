#pragma once

// What the C API's opaque handles are. Every handle is registered while it
// lives, so a call on a destroyed or foreign pointer is refused with
// DFM_ERROR_INVALID_HANDLE instead of touching freed memory.

#include <cstdint>
#include <memory>
#include <mutex>
#include <new>
#include <string>
#include <vector>

#include "deform/async_session.hpp"
#include "deform/mesh_model.hpp"
#include "dualform/dualform.h"
#include "pick/embree_scene.hpp"
#include "solver/thread_pool.hpp"

namespace dfm::sdk {

// The host's hooks, or malloc/free when both are NULL. allocate throws
// std::bad_alloc when the hook returns NULL.
void* host_allocate(const dfm_allocator& hooks, std::size_t size, std::size_t alignment);
void host_deallocate(const dfm_allocator& hooks, void* memory, std::size_t size);

struct ContextState {
    dfm_allocator allocator{};
    dfm_log_fn log = nullptr;
    void* log_user = nullptr;
    std::uint32_t worker_count = 1;
    std::string models_directory;  // empty: model:NAME is not found

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

// A mesh's history of rest poses: bakes push, undo and redo move between.
struct MeshState {
    std::shared_ptr<const ContextState> context;
    mutable std::mutex mutex;
    std::shared_ptr<const deform::MeshModel> model;
    std::vector<std::shared_ptr<const deform::MeshModel>> undo;
    std::vector<std::shared_ptr<const deform::MeshModel>> redo;
    // Built on the first pick for `scene_model`, refit after a bake or undo.
    pick::EmbreeScene scene;
    std::shared_ptr<const deform::MeshModel> scene_model;

    std::shared_ptr<const deform::MeshModel> current() const {
        std::lock_guard<std::mutex> lock(mutex);
        return model;
    }
};

}  // namespace dfm::sdk

struct dfm_context {
    std::shared_ptr<const dfm::sdk::ContextState> state;
};

struct dfm_mesh {
    std::shared_ptr<dfm::sdk::MeshState> state;
};

struct dfm_roi {
    std::shared_ptr<dfm::sdk::MeshState> mesh;
    std::vector<std::uint32_t> vertices;  // ascending
};

struct dfm_session {
    std::shared_ptr<dfm::sdk::MeshState> mesh;
    std::shared_ptr<const dfm::deform::MeshModel> model;  // the rest pose it edits
    std::vector<std::uint32_t> roi;
    std::vector<std::vector<std::uint32_t>> groups;
    dfm::deform::DeformSettings settings;
    std::unique_ptr<dfm::solver::ThreadPool> pool;
    std::unique_ptr<dfm::deform::AsyncSession> async;
    // The host's staged targets, one per handle vertex in group order, and
    // the handles' rest positions the group transforms apply to.
    std::mutex staging_mutex;
    std::vector<glm::dvec3> staged;
    std::vector<glm::dvec3> handle_rest;
    std::vector<std::size_t> group_offsets;  // group g: [offsets[g], offsets[g + 1])
    std::vector<glm::dvec3> submitting;      // staged, copied out under the mutex
    std::vector<glm::dvec3> rest_normals;    // of the whole rest pose
};

namespace dfm::sdk {

enum class Kind : std::uint8_t { context, mesh, roi, session };

void register_handle(const void* handle, Kind kind);
void unregister_handle(const void* handle);
bool is_live(const void* handle, Kind kind);

inline std::shared_ptr<const ContextState> context_of(const dfm_context& c) {
    return c.state;
}
inline std::shared_ptr<const ContextState> context_of(const dfm_mesh& m) {
    return m.state->context;
}
inline std::shared_ptr<const ContextState> context_of(const dfm_roi& r) {
    return r.mesh->context;
}
inline std::shared_ptr<const ContextState> context_of(const dfm_session& s) {
    return s.mesh->context;
}

// Creates a handle object in memory from the context's allocator.
template <class T, class... Args>
T* host_new(const ContextState& context, Kind kind, Args&&... args) {
    void* memory = context.allocate(sizeof(T), alignof(T));
    T* object = nullptr;
    try {
        object = new (memory) T{std::forward<Args>(args)...};
        register_handle(object, kind);
    } catch (...) {
        if (object != nullptr) object->~T();
        context.deallocate(memory, sizeof(T));
        throw;
    }
    return object;
}

template <class T>
void host_delete(T* object) {
    // The object may hold the last reference to the context; keep it alive
    // until its memory is returned.
    std::shared_ptr<const ContextState> context = context_of(*object);
    unregister_handle(object);
    object->~T();
    context->deallocate(object, sizeof(T));
}

}  // namespace dfm::sdk
