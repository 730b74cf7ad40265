#include <cstdlib>
#include <memory>

#include "c_boundary.hpp"
#include "objects.hpp"

namespace dfm::sdk {

void* host_allocate(const dfm_allocator& hooks, std::size_t size, std::size_t alignment) {
    void* memory = nullptr;
    if (hooks.alloc != nullptr) {
        memory = hooks.alloc(hooks.user, size, alignment);
    } else {
        const std::size_t rounded = (size + alignment - 1) / alignment * alignment;
        memory = std::aligned_alloc(alignment, rounded);
    }
    if (memory == nullptr) throw std::bad_alloc();
    return memory;
}

void host_deallocate(const dfm_allocator& hooks, void* memory, std::size_t size) {
    if (hooks.free != nullptr) {
        hooks.free(hooks.user, memory, size);
    } else {
        std::free(memory);
    }
}

void ContextState::emit(dfm_log_level level, dfm_log_id id, const std::string& message) const {
    if (log != nullptr) log(log_user, level, id, message.c_str());
}

}  // namespace dfm::sdk

using namespace dfm::sdk;

extern "C" DFM_API uint32_t dfm_version(void) {
    return DFM_VERSION;
}

extern "C" DFM_API dfm_result dfm_context_create(const dfm_context_desc* desc, dfm_context** out) {
    constexpr const char* fn = "dfm_context_create";
    if (out == nullptr) return report(fn, DFM_ERROR_INVALID_ARGUMENT, "out is NULL");
    *out = nullptr;
    const dfm_context_desc defaults = {};
    const dfm_context_desc& d = desc != nullptr ? *desc : defaults;
    if ((d.allocator.alloc == nullptr) != (d.allocator.free == nullptr)) {
        return report(fn, DFM_ERROR_INVALID_ARGUMENT,
                      "allocator: give both alloc and free, or neither");
    }
    if (d.worker_count > 256) {
        return report(fn, DFM_ERROR_INVALID_ARGUMENT,
                      "worker_count " + std::to_string(d.worker_count) + " is above 256");
    }
    return guarded(fn, [&] {
        auto state = std::allocate_shared<ContextState>(HostAllocator<ContextState>(d.allocator));
        state->allocator = d.allocator;
        state->log = d.log;
        state->log_user = d.log_user;
        state->worker_count = d.worker_count == 0 ? 1 : d.worker_count;
        if (d.models_directory != nullptr) state->models_directory = d.models_directory;
        *out = host_new<dfm_context>(*state, Kind::context,
                                     std::shared_ptr<const ContextState>(state));
        return DFM_OK;
    });
}

extern "C" DFM_API void dfm_context_destroy(dfm_context* context) {
    if (!is_live(context, Kind::context)) return;
    host_delete(context);
}
