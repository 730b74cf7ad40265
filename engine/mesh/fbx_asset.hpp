#pragma once

#include <cstdint>
#include <vector>

#include <glm/mat4x4.hpp>

#include "mesh/fbx_document.hpp"
#include "mesh/fbx_scene.hpp"

namespace dfm::mesh {

// One mesh geometry's control points as loaded: host vertices
// [first_vertex, first_vertex + count), taken from the file's space to
// Dualform's (metres, +Y up) by `world` (units and axes, then the model's
// global transform, or for a skinned mesh the skin's bind transform).
struct FbxGeometryRange {
    std::size_t geometry = 0;  // into FbxScene::geometries
    std::uint32_t first_vertex = 0;
    std::uint32_t count = 0;
    glm::dmat4 world{1.0};
};

// What saving an FBX back needs: the file's bytes and node tree, untouched,
// what the scan read of it, and where the host's vertices (the control
// points of the instanced meshes, in order) came from.
struct FbxAsset {
    FbxDocument document;
    FbxScene scene;
    std::vector<FbxGeometryRange> ranges;
};

}  // namespace dfm::mesh
