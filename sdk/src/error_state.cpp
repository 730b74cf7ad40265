#include "error_state.hpp"

#include <cstdio>
#include <cstring>

namespace {

// A fixed buffer: recording an error must work when memory has run out.
struct LastError {
    dfm_result code = DFM_OK;
    char message[1024] = {};
};

thread_local LastError last_error;

}  // namespace

extern "C" DFM_API dfm_result dfm_detail_set_error(dfm_result code, const char* message) {
    last_error.code = code;
    std::snprintf(last_error.message, sizeof last_error.message, "%s", message ? message : "");
    return code;
}

extern "C" DFM_API const char* dfm_last_error_message(void) {
    return last_error.message;
}

extern "C" DFM_API dfm_result dfm_last_error_code(void) {
    return last_error.code;
}

namespace dfm::sdk {

dfm_result fail_parts(dfm_result code, const char* function, const char* what) noexcept {
    last_error.code = code;
    std::snprintf(last_error.message, sizeof last_error.message, "%s: %s", function, what);
    return code;
}

}  // namespace dfm::sdk
