#pragma once

#include <string>
#include <vector>

#include "core/status.hpp"
#include "mesh/gltf_asset.hpp"
#include "mesh/gltf_model.hpp"

namespace dfm::mesh {

// An accessor's elements as doubles, `components` per element: floats as
// they are, normalized integers scaled to [0, 1] or [-1, 1], other integers
// as their values; a sparse accessor's substitutions applied. Every byte
// range is checked against its buffer view and buffer first. `what` names
// the accessor's use in messages ("mesh 0 primitive 1 POSITION").
Status read_accessor(const tinygltf::Model& model, int index, int components,
                     const std::string& what, std::vector<double>& out);

// The accessor's element count, type and component type checked; the
// message names `what` and the accessor.
Status check_accessor_shape(const tinygltf::Model& model, int index, int type,
                            const std::string& what);

// Where the accessor's elements lie when they can be overwritten in place
// (see GltfSlot); `claimed` marks per buffer the bytes something else reads.
GltfSlot slot_of(const tinygltf::Model& model, int index,
                 const std::vector<std::vector<bool>>& claimed);

// Per buffer, the bytes read by accessors not in `rewritten`, by images and
// by buffer views no accessor uses.
std::vector<std::vector<bool>> claimed_bytes(const tinygltf::Model& model,
                                             const std::vector<bool>& rewritten);

}  // namespace dfm::mesh
