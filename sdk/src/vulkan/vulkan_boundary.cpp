#include "vulkan_boundary.hpp"

#include <cstdio>

namespace dfm::sdk {

// libdualform keeps its own fail_parts private; this library formats the
// message itself and hands it to the exported dfm_detail_set_error, so both
// libraries share one per-thread error slot.
dfm_result fail_parts(dfm_result code, const char* function, const char* what) noexcept {
    char message[1024];
    std::snprintf(message, sizeof message, "%s: %s", function, what);
    return dfm_detail_set_error(code, message);
}

dfm_result report_render(const char* function, const render::RenderStatus& status) {
    switch (status.fault()) {
        case render::Fault::none: return DFM_OK;
        case render::Fault::invalid_argument:
            return report(function, DFM_ERROR_INVALID_ARGUMENT, status.message());
        case render::Fault::unsupported:
            return report(function, DFM_ERROR_UNSUPPORTED, status.message());
        case render::Fault::io_error: return report(function, DFM_ERROR_IO, status.message());
        case render::Fault::out_of_memory:
            return report(function, DFM_ERROR_OUT_OF_MEMORY, status.message());
        case render::Fault::device: return report(function, DFM_ERROR_DEVICE, status.message());
    }
    return report(function, DFM_ERROR_DEVICE, status.message());
}

}  // namespace dfm::sdk
