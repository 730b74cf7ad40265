#pragma once

#include <string_view>

#include "core/status.hpp"
#include "mesh/gltf_asset.hpp"
#include "mesh/gltf_model.hpp"
#include "mesh/load.hpp"
#include "mesh/skin.hpp"

namespace dfm::mesh {

// What poses the loaded vertices: the skins of the nodes that instance them
// (JOINTS_n and WEIGHTS_n, every set, normalised to sum 1; the inverse bind
// matrices), the whole node graph, every animation, and the morph targets
// of the loaded meshes with their default weights. Vertex arrays are per
// host vertex of `asset`'s ranges; morph deltas are in the space the
// vertices were loaded in. Leaves `skin` empty when nothing poses the
// vertices. The samplers that drive morph weights go to
// `asset.weight_samplers`, for a save that adds a target. Errors name the
// file, node, skin, mesh, accessor or vertex; channels that cannot apply are
// skipped with a warning.
Status read_gltf_skin(const tinygltf::Model& model, std::string_view source, GltfAsset& asset,
                      Skin& skin, LoadReport& report);

}  // namespace dfm::mesh
