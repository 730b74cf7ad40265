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

namespace {

// What struct_size 0 stands for: dfm_context_desc as version 0.2 had it.
constexpr std::size_t context_desc_0_2 = DFM_END_OF(dfm_context_desc, models_directory);

}  // namespace

extern "C" DFM_API uint32_t dfm_version(void) {
    return DFM_VERSION;
}

extern "C" DFM_API bool dfm_version_compatible(uint32_t header_version) {
    const std::uint32_t major = header_version / 10000;
    const std::uint32_t minor = header_version / 100 % 100;
    if (major != DFM_VERSION_MAJOR) return false;
    // Before 1.0 every minor version may change the ABI.
    return major == 0 ? minor == DFM_VERSION_MINOR : minor <= DFM_VERSION_MINOR;
}

extern "C" DFM_API dfm_result dfm_context_create(const dfm_context_desc* desc, dfm_context** out) {
    constexpr const char* fn = "dfm_context_create";
    return guarded(fn, [&] {
        if (out == nullptr) return report(fn, DFM_ERROR_INVALID_ARGUMENT, "out is NULL");
        *out = nullptr;
        dfm_context_desc d{};
        if (desc != nullptr) {
            if (dfm_result r = read_descriptor(fn, "desc", desc, context_desc_0_2, d);
                r != DFM_OK) {
                return r;
            }
        }
        if (d.header_version != 0 && !dfm_version_compatible(d.header_version)) {
            return report(fn, DFM_ERROR_UNSUPPORTED,
                          "the caller was built with the header of version " +
                              std::to_string(d.header_version) + ", this library is version " +
                              std::to_string(DFM_VERSION));
        }
        if ((d.allocator.alloc == nullptr) != (d.allocator.free == nullptr)) {
            return report(fn, DFM_ERROR_INVALID_ARGUMENT,
                          "allocator: give both alloc and free, or neither");
        }
        if (d.pick_thread_count > 1024) {
            return report(
                fn, DFM_ERROR_INVALID_ARGUMENT,
                "pick_thread_count " + std::to_string(d.pick_thread_count) + " is above 1024");
        }
        if (d.worker_count > 256) {
            return report(fn, DFM_ERROR_INVALID_ARGUMENT,
                          "worker_count " + std::to_string(d.worker_count) + " is above 256");
        }
        auto state = std::allocate_shared<ContextState>(HostAllocator<ContextState>(d.allocator));
        state->allocator = d.allocator;
        state->log = d.log;
        state->log_user = d.log_user;
        state->worker_count = d.worker_count == 0 ? 1 : d.worker_count;
        state->pick_thread_count = d.pick_thread_count;
        if (d.models_directory != nullptr) state->models_directory = d.models_directory;
        if (d.reference_folder != nullptr) state->reference_folder = d.reference_folder;
        *out = host_new<ContextObject>(*state, std::shared_ptr<const ContextState>(state));
        return DFM_OK;
    });
}

extern "C" DFM_API void dfm_context_destroy(dfm_context* context) {
    guarded_void("dfm_context_destroy", [&] { host_delete<ContextObject>(context); });
}
