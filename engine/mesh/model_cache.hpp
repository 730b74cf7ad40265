#pragma once

#include <filesystem>
#include <string_view>

#include "core/status.hpp"

namespace dfm::mesh {

// Turns "model:NAME" into NAME.off in `models_directory` (the folder
// tools/fetch-models fills; the caller says where it is, the library never
// guesses), and passes any other spec through as a path (relative ones
// against `base`). A missing models folder or cached model is an error that
// says how to fix it.
Status resolve_mesh_spec(std::string_view spec, const std::filesystem::path& base,
                         const std::filesystem::path& models_directory, std::filesystem::path& out);

}  // namespace dfm::mesh
