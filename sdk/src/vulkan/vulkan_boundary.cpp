#include <cstdio>

#include "error_state.hpp"

namespace dfm::sdk {

// libdualform keeps its own fail_parts private; this library formats the
// message itself and hands it to the exported dfm_detail_set_error, so both
// libraries share one per-thread error slot.
dfm_result fail_parts(dfm_result code, const char* function, const char* what) noexcept {
    char message[1024];
    std::snprintf(message, sizeof message, "%s: %s", function, what);
    return dfm_detail_set_error(code, message);
}

}  // namespace dfm::sdk
