#include <chrono>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <system_error>
#include <type_traits>

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

using namespace dfm;
using namespace dfm::sdk;

namespace {

// The longest budget dfm_context_step takes as one: a day.
constexpr std::uint64_t longest_step_us = 86'400'000'000;

// The work mode and its workers, checked; `out` for the scheduler.
dfm_result work_from(const char* fn, const dfm_context_desc& d, jobs::SchedulerConfig& out) {
    std::underlying_type_t<dfm_work_mode> mode;  // read as an integer: a host may pass any value
    std::memcpy(&mode, &d.work_mode, sizeof mode);
    const bool has_job_system = d.job_system.enqueue != nullptr || d.job_system.user != nullptr;
    out.workers = d.worker_count == 0 ? 1 : d.worker_count;
    switch (mode) {
        case DFM_WORK_POOL: out.mode = jobs::Mode::pool; break;
        case DFM_WORK_JOB_SYSTEM:
            if (d.job_system.enqueue == nullptr) {
                return report(fn, DFM_ERROR_INVALID_ARGUMENT,
                              "job_system.enqueue is NULL: DFM_WORK_JOB_SYSTEM needs the host's "
                              "job system");
            }
            out.mode = jobs::Mode::host_jobs;
            return DFM_OK;
        case DFM_WORK_HOST_STEPPED:
            if (out.workers > 1) {
                return report(fn, DFM_ERROR_INVALID_ARGUMENT,
                              "worker_count " + std::to_string(d.worker_count) +
                                  " with DFM_WORK_HOST_STEPPED: the host's one thread runs the "
                                  "work (0 or 1)");
            }
            out.mode = jobs::Mode::host_stepped;
            break;
        default:
            return report(fn, DFM_ERROR_INVALID_ARGUMENT,
                          "work_mode: unknown mode " + std::to_string(mode) +
                              " (DFM_WORK_POOL, _JOB_SYSTEM or _HOST_STEPPED expected)");
    }
    if (has_job_system) {
        return report(fn, DFM_ERROR_INVALID_ARGUMENT,
                      "job_system is set, but work_mode is not DFM_WORK_JOB_SYSTEM");
    }
    return DFM_OK;
}

// Hands a scheduler's job to the host's job system (dfm_job_system).
void enqueue_on_host(void* user, void* job) {
    const auto* host = static_cast<const dfm_job_system*>(user);
    host->enqueue(host->user, static_cast<dfm_job*>(job));
}

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
            if (dfm_result r = read_descriptor(fn, "desc", desc, d); r != DFM_OK) {
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
        jobs::SchedulerConfig work;
        if (dfm_result r = work_from(fn, d, work); r != DFM_OK) return r;
        auto state = std::allocate_shared<ContextState>(HostAllocator<ContextState>(d.allocator));
        state->allocator = d.allocator;
        state->log = d.log;
        state->log_user = d.log_user;
        state->pick_thread_count = d.pick_thread_count;
        if (d.models_directory != nullptr) state->models_directory = d.models_directory;
        if (d.reference_folder != nullptr) state->reference_folder = d.reference_folder;
        state->job_system = d.job_system;
        work.host = {&enqueue_on_host, &state->job_system};
        try {
            state->scheduler = std::make_unique<jobs::Scheduler>(work);
        } catch (const std::system_error& e) {
            return report(fn, DFM_ERROR_OUT_OF_MEMORY,
                          std::string("could not start the context's worker threads: ") + e.what());
        }
        *out = host_new<ContextObject>(*state, std::shared_ptr<const ContextState>(state));
        return DFM_OK;
    });
}

extern "C" DFM_API void dfm_context_destroy(dfm_context* context) {
    guarded_void("dfm_context_destroy", [&] { host_delete<ContextObject>(context); });
}

extern "C" DFM_API void dfm_job_run(dfm_job* job) {
    guarded_void("dfm_job_run", [&] {
        if (job != nullptr) jobs::Scheduler::run_job(job);
    });
}

extern "C" DFM_API dfm_result dfm_context_step(dfm_context* context, uint64_t budget_us,
                                               bool* work_left) {
    constexpr const char* fn = "dfm_context_step";
    return guarded(fn, [&] {
        if (work_left != nullptr) *work_left = false;
        ContextObject* c = resolve_context(context);
        if (c == nullptr) return bad_handle(fn, "context", context);
        jobs::Scheduler& scheduler = *c->state->scheduler;
        if (scheduler.mode() != jobs::Mode::host_stepped) {
            return report(fn, DFM_ERROR_UNSUPPORTED,
                          "the context was not created with DFM_WORK_HOST_STEPPED: its work runs "
                          "by itself");
        }
        const auto deadline =
            budget_us == 0 ? jobs::Clock::time_point::max()
                           : jobs::Clock::now() +
                                 std::chrono::microseconds(std::min(budget_us, longest_step_us));
        const bool left = scheduler.step(deadline);
        if (work_left != nullptr) *work_left = left;
        return DFM_OK;
    });
}
