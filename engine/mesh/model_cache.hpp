#pragma once

#include <filesystem>
#include <string_view>

#include "core/status.hpp"

namespace dfm::mesh {

// The real-model cache that tools/fetch-models fills: $DUALFORM_MODELS, or
// $HOME/.cache/dualform/models.
std::filesystem::path models_directory();

// Turns "model:NAME" into the cached NAME.off, and passes any other spec
// through as a path (relative ones against `base`). A missing cached model
// is an error that says how to fetch it.
Status resolve_mesh_spec(std::string_view spec, const std::filesystem::path& base,
                         std::filesystem::path& out);

}  // namespace dfm::mesh
