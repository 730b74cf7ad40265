#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "mesh/load.hpp"
#include "mesh/seam_weld.hpp"
#include "mesh/skin.hpp"

namespace dfm::mesh {

// What must agree for copies at one position to join.
enum class WeldBy {
    // Their influences (joints and weights). Morph deltas do not split
    // copies, so glTF's bind-pose weld stays what it was before skins were
    // read; a surface vertex takes its lowest copy's deltas, and
    // weld_skinned warns where they differ.
    skin,
    // Their influences and every morph target's delta (FBX's control points,
    // a format new to the weld).
    skin_and_morphs,
};

// One class per distinct skin of a host vertex, as `by` says. Copies at one
// position join only within a class (weld_seams), so a surface vertex has
// one skin and posing cannot crack a seam. Empty for an empty skin.
std::vector<std::uint32_t> skin_classes(const Skin& skin, WeldBy by);

// The skin per surface vertex: each takes its lowest copy's influences and
// morph deltas (its copies agree, by the classes above).
Skin skin_on_surface(const Skin& host_skin, const SeamWeld& weld);

// weld_seams with the skin's classes, and the skin moved to the surface
// (`surface_skin` null when `host_skin` is empty); warnings in `report`
// (naming `source`) count the positions whose copies stayed apart and the
// surface vertices whose copies' morph deltas differ.
void weld_skinned(const Mesh& split, const Skin& host_skin, WeldBy by, const WeldOptions& options,
                  const std::string& source, Mesh& surface, SeamWeld& weld,
                  std::shared_ptr<const Skin>& surface_skin, LoadReport& report);

}  // namespace dfm::mesh
