#include "c_boundary.hpp"

extern "C" DFM_API const char* dfm_result_name(dfm_result result) {
    switch (result) {
        case DFM_OK: return "DFM_OK";
        case DFM_ERROR_INVALID_ARGUMENT: return "DFM_ERROR_INVALID_ARGUMENT";
        case DFM_ERROR_NOT_FOUND: return "DFM_ERROR_NOT_FOUND";
        case DFM_ERROR_IO: return "DFM_ERROR_IO";
        case DFM_ERROR_PARSE: return "DFM_ERROR_PARSE";
        case DFM_ERROR_OUT_OF_RANGE: return "DFM_ERROR_OUT_OF_RANGE";
        case DFM_ERROR_UNSUPPORTED: return "DFM_ERROR_UNSUPPORTED";
        case DFM_ERROR_OUT_OF_MEMORY: return "DFM_ERROR_OUT_OF_MEMORY";
        case DFM_ERROR_NUMERICAL: return "DFM_ERROR_NUMERICAL";
        case DFM_ERROR_INVALID_HANDLE: return "DFM_ERROR_INVALID_HANDLE";
        case DFM_ERROR_BUSY: return "DFM_ERROR_BUSY";
        case DFM_ERROR_DEVICE: return "DFM_ERROR_DEVICE";
        case DFM_ERROR_CANCELLED: return "DFM_ERROR_CANCELLED";
        case DFM_ERROR_INTERNAL: return "DFM_ERROR_INTERNAL";
    }
    return "DFM_ERROR_UNKNOWN";
}
