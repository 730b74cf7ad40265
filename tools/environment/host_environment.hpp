#pragma once

#include <filesystem>

// What the tools and tests read from the environment and hand to the
// library through its descriptors; the library itself reads none.
namespace dfm::tools {

// $DUALFORM_MODELS, or $HOME/.cache/dualform/models (the user database's home
// folder when HOME is unset): where tools/fetch-models puts the real models.
std::filesystem::path models_folder_from_environment();

// DUALFORM_VALIDATION=1: turn on the Vulkan validation layer.
bool validation_from_environment();

}  // namespace dfm::tools
