#pragma once

#include "mesh/mesh.hpp"

namespace dfm::mesh {

// One step of Loop subdivision: every triangle becomes four. The original
// vertices keep their indices (moved by Loop's vertex rule), and the edge
// vertices follow, so vertex indices chosen on the coarse mesh still name
// the same places on the fine one. Boundary and non-manifold edges use the
// boundary rules (edge midpoints; boundary vertices smoothed along the
// boundary only).
Mesh subdivide_loop(const Mesh& mesh);

}  // namespace dfm::mesh
