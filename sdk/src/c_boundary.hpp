#pragma once

#include <cstddef>
#include <cstring>
#include <exception>
#include <new>
#include <string>

#include "core/status.hpp"
#include "descriptor_layouts.hpp"
#include "dualform/dualform.h"
#include "error_state.hpp"

namespace dfm::sdk {

// The C API's code for an engine error category (one-to-one but for ok).
inline dfm_result to_result(Errc code) {
    switch (code) {
        case Errc::ok: return DFM_OK;
        case Errc::invalid_argument: return DFM_ERROR_INVALID_ARGUMENT;
        case Errc::not_found: return DFM_ERROR_NOT_FOUND;
        case Errc::io_error: return DFM_ERROR_IO;
        case Errc::parse_error: return DFM_ERROR_PARSE;
        case Errc::out_of_range: return DFM_ERROR_OUT_OF_RANGE;
        case Errc::unsupported: return DFM_ERROR_UNSUPPORTED;
        case Errc::out_of_memory: return DFM_ERROR_OUT_OF_MEMORY;
        case Errc::numerical: return DFM_ERROR_NUMERICAL;
        case Errc::internal: return DFM_ERROR_INTERNAL;
        case Errc::cancelled: return DFM_ERROR_CANCELLED;
        case Errc::device: return DFM_ERROR_DEVICE;
        case Errc::busy: return DFM_ERROR_BUSY;
    }
    return DFM_ERROR_INTERNAL;
}

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

// The one guard around the body of every C entry point: no exception leaves
// it. bad_alloc becomes DFM_ERROR_OUT_OF_MEMORY; anything else is a defect of
// ours, DFM_ERROR_INTERNAL with its text. The handlers record the message
// without allocating.
template <class Body>
dfm_result guarded(const char* function, Body&& body) noexcept {
    try {
        return body();
    } catch (const std::bad_alloc&) {
        return fail_parts(DFM_ERROR_OUT_OF_MEMORY, function, "out of memory");
    } catch (const std::exception& e) {
        return fail_parts(DFM_ERROR_INTERNAL, function, e.what());
    } catch (...) {
        return fail_parts(DFM_ERROR_INTERNAL, function, "an unknown exception");
    }
}

// The same for the calls that return nothing (destroy): a failure is
// recorded as the thread's last error.
template <class Body>
void guarded_void(const char* function, Body&& body) noexcept {
    guarded(function, [&] {
        body();
        return DFM_OK;
    });
}

// DFM_ERROR_INVALID_HANDLE naming the parameter, NULL or not live.
inline dfm_result bad_handle(const char* function, const char* parameter, const void* handle) {
    return report(function, DFM_ERROR_INVALID_HANDLE,
                  std::string(parameter) +
                      (handle == nullptr ? " is NULL" : " is not a live handle of its kind"));
}

// The bytes of a host's struct that begins with struct_size: what its
// struct_size says, 0 standing for the first layout (descriptor_layouts.hpp).
template <class Desc>
std::size_t host_struct_size(std::uint32_t struct_size) {
    return struct_size != 0 ? struct_size : FirstLayout<Desc>::size;
}

// Copies a host descriptor that begins with `uint32_t struct_size` into
// `out` (zeroed first), reading only the bytes the host's struct has. A
// larger struct than ours is accepted only when the bytes we do not know
// are zero.
template <class Desc>
dfm_result read_descriptor(const char* function, const char* name, const Desc* in, Desc& out) {
    std::memset(&out, 0, sizeof out);
    if (in == nullptr)
        return report(function, DFM_ERROR_INVALID_ARGUMENT, std::string(name) + " is NULL");
    std::uint32_t struct_size = 0;
    std::memcpy(&struct_size, in, sizeof struct_size);
    const std::size_t size = host_struct_size<Desc>(struct_size);
    if (size < sizeof struct_size) {
        return report(function, DFM_ERROR_INVALID_ARGUMENT,
                      std::string(name) + "->struct_size " + std::to_string(size) +
                          " is smaller than the field itself");
    }
    const auto* bytes = reinterpret_cast<const unsigned char*>(in);
    for (std::size_t i = sizeof(Desc); i < size; ++i) {
        if (bytes[i] != 0) {
            return report(function, DFM_ERROR_UNSUPPORTED,
                          std::string(name) + " is " + std::to_string(size) +
                              " bytes, of which this library (version " +
                              std::to_string(DFM_VERSION) + ") knows " +
                              std::to_string(sizeof(Desc)) + "; byte " + std::to_string(i) +
                              " of a newer field is set");
        }
    }
    std::memcpy(&out, in, size < sizeof(Desc) ? size : sizeof(Desc));
    return DFM_OK;
}

}  // namespace dfm::sdk
