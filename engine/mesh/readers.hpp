#pragma once

#include <string_view>

#include "core/status.hpp"
#include "mesh/mesh_builder.hpp"

// One reader per format, each filling a MeshBuilder from bytes in memory.
namespace dfm::mesh {

Status read_off(std::string_view text, std::string_view source, MeshBuilder& builder);
Status read_obj(std::string_view text, std::string_view source, MeshBuilder& builder);
Status read_ply(std::string_view bytes, std::string_view source, MeshBuilder& builder);

}  // namespace dfm::mesh
