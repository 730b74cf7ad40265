#pragma once

#include <exception>
#include <new>
#include <string>

#include "core/status.hpp"
#include "dualform/dualform.h"
#include "error_state.hpp"

namespace dfm::sdk {

dfm_result to_result(Errc code);

// Records a failing engine status under the C function's name; DFM_OK passes.
inline dfm_result report(const char* function, const Status& status) {
    if (status.is_ok()) return DFM_OK;
    std::string message = function;
    message += ": ";
    message += status.message();
    return fail(to_result(status.code()), message);
}

inline dfm_result report(const char* function, dfm_result code, const std::string& what) {
    std::string message = function;
    message += ": ";
    message += what;
    return fail(code, message);
}

// Runs the body of one C entry point: no exception leaves it. bad_alloc becomes
// DFM_ERROR_OUT_OF_MEMORY; anything else is a defect reported as
// DFM_ERROR_INVALID_ARGUMENT with its text, instead of terminating the host.
template <class Body>
dfm_result guarded(const char* function, Body&& body) noexcept {
    try {
        return body();
    } catch (const std::bad_alloc&) {
        return fail_parts(DFM_ERROR_OUT_OF_MEMORY, function, "out of memory");
    } catch (const std::exception& e) {
        return report(function, DFM_ERROR_INVALID_ARGUMENT,
                      std::string("internal error: ") + e.what());
    } catch (...) {
        return report(function, DFM_ERROR_INVALID_ARGUMENT, "internal error");
    }
}

}  // namespace dfm::sdk

namespace dfm::sdk {

// DFM_ERROR_INVALID_HANDLE naming the parameter, NULL or not live.
inline dfm_result bad_handle(const char* function, const char* parameter, const void* handle) {
    return report(function, DFM_ERROR_INVALID_HANDLE,
                  std::string(parameter) +
                      (handle == nullptr ? " is NULL" : " is not a live handle of its kind"));
}

}  // namespace dfm::sdk
