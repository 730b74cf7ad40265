#include "mesh/where.hpp"

namespace dfm::mesh {

std::string Where::prefix() const {
    std::string p(source);
    if (is_byte_offset) {
        p += ": byte " + std::to_string(position) + ": ";
    } else {
        p += ':' + std::to_string(position) + ": ";
    }
    return p;
}

Status Where::error(Errc code, std::string_view what) const {
    return Status(code, prefix() + std::string(what));
}

}  // namespace dfm::mesh
