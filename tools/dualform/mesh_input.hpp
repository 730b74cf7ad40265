#pragma once

#include <string_view>

#include "core/status.hpp"
#include "mesh/load.hpp"
#include "mesh/mesh.hpp"

namespace dfm::cli {

// Loads a path or a "model:NAME" and prints the load's warnings on stderr.
Status load_mesh_input(std::string_view spec, mesh::Mesh& mesh, mesh::LoadReport& report);

}  // namespace dfm::cli
