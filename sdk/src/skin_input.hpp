#pragma once

#include <cstddef>

#include "core/status.hpp"
#include "dualform/dualform.h"
#include "mesh/skin.hpp"

namespace dfm::sdk {

// A host's dfm_skin_input for `vertex_count` host vertices, read through
// its strides and types into the engine's skin (mesh::skin_from_arrays
// checks the values). Errc::invalid_argument names the field that is NULL,
// too large or of an unknown type.
Status read_skin_input(const dfm_skin_input& in, std::size_t vertex_count, mesh::Skin& out);

}  // namespace dfm::sdk
