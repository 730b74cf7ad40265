#include "core/status.hpp"

namespace dfm {

const char* errc_name(Errc code) {
    switch (code) {
        case Errc::ok: return "ok";
        case Errc::invalid_argument: return "invalid argument";
        case Errc::not_found: return "not found";
        case Errc::io_error: return "i/o error";
        case Errc::parse_error: return "parse error";
        case Errc::out_of_range: return "out of range";
        case Errc::unsupported: return "unsupported";
        case Errc::out_of_memory: return "out of memory";
        case Errc::numerical: return "numerical failure";
        case Errc::internal: return "internal error";
        case Errc::cancelled: return "cancelled";
        case Errc::device: return "device failure";
        case Errc::busy: return "busy";
    }
    return "unknown error";
}

}  // namespace dfm
