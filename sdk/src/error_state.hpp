#pragma once

#include <string>

#include "dualform/dualform.h"

// The per-thread last-error record behind dfm_last_error_message(). It lives in
// libdualform; the renderer library reports through the exported
// dfm_detail_set_error so that one message slot serves both.
extern "C" DFM_API dfm_result dfm_detail_set_error(dfm_result code, const char* message);

namespace dfm::sdk {

// "function: what", written without allocating (safe when memory ran out).
dfm_result fail_parts(dfm_result code, const char* function, const char* what) noexcept;

inline dfm_result fail(dfm_result code, const std::string& message) {
    return dfm_detail_set_error(code, message.c_str());
}

}  // namespace dfm::sdk
