#pragma once

#include <cstdint>
#include <map>
#include <set>
#include <string>
#include <vector>

#include <glm/mat4x4.hpp>

#include "core/status.hpp"
#include "mesh/fbx_document.hpp"
#include "mesh/load.hpp"

// What Dualform reads of an FBX file from its node tree itself, checked
// before Assimp sees the file (docs/fbx.md): the global settings, the
// meshes the scene instances with their control points and polygons, their
// skin clusters and blend shape channels, and the model hierarchy's shape.
namespace dfm::mesh {

// The file's units and axes: `to_metres_y_up` takes a point in the file's
// space to metres in glTF's axes (+Y up, +Z front, right-handed): the
// rotation from the file's UpAxis and FrontAxis (their signs included; the
// third axis follows by the right hand, as Blender's importer takes it),
// scaled by UnitScaleFactor / 100 (FBX counts centimetres per unit).
struct FbxSettings {
    int up_axis = 1, up_sign = 1;
    int front_axis = 2, front_sign = 1;
    double centimetres_per_unit = 1.0;
    glm::dmat4 to_metres_y_up{1.0};
};

// A skin cluster: the control points one joint moves and its bind pose.
struct FbxCluster {
    std::uint32_t node = no_index;  // the Deformer node
    std::uint64_t id = 0;
    std::uint64_t model = 0;  // the Model (joint) it binds; 0: none connected
    std::string model_name;
    std::vector<std::uint32_t> indexes;  // control points, each < the geometry's count
    std::vector<double> weights;
    // The mesh in the joint's space at bind time (what the file stores as
    // Transform: the mesh's global bind transform is TransformLink * it).
    glm::dmat4 transform{1.0};
    glm::dmat4 transform_link{1.0};  // the joint's global transform at bind time
};

// A blend shape channel with its (last) shape: deltas at control points.
struct FbxShapeChannel {
    std::uint32_t channel_node = no_index;  // the BlendShapeChannel deformer
    std::uint32_t shape_node = no_index;    // its Shape geometry
    std::string name;                       // the channel's name
    double deform_percent = 0.0;            // its default weight, in percent
    std::size_t shapes = 0;                 // shapes in the channel (in-betweens beyond 1)
    std::vector<std::uint32_t> indexes;     // ascending
    std::vector<double> deltas;             // 3 per index, in the geometry's space
};

// A mesh geometry the scene instances, with its first model.
struct FbxGeometry {
    std::uint32_t node = no_index;  // the Geometry node
    std::uint64_t id = 0;
    std::string name;
    std::uint32_t model_node = no_index;
    std::uint64_t model = 0;
    std::string model_name;
    std::uint32_t vertices_node = no_index;  // its "Vertices" child
    std::vector<double> control_points;      // 3 per control point
    // Polygon p's corners are corners[polygon_start[p] .. polygon_start[p + 1]),
    // control points in the file's order (PolygonVertexIndex decoded).
    std::vector<std::uint32_t> corners;
    std::vector<std::uint32_t> polygon_start;
    std::uint32_t skin_node = no_index;
    std::vector<FbxCluster> clusters;
    std::uint32_t blend_shape_node = no_index;  // the first BlendShape deformer
    std::uint64_t blend_shape = 0;
    std::vector<FbxShapeChannel> channels;

    std::size_t control_point_count() const { return control_points.size() / 3; }
    std::size_t polygon_count() const {
        return polygon_start.empty() ? 0 : polygon_start.size() - 1;
    }
};

struct FbxScene {
    FbxSettings settings;
    std::vector<FbxGeometry> geometries;  // in the order of the Objects section
    std::uint32_t objects_node = no_index;
    std::uint32_t connections_node = no_index;
    std::uint32_t definitions_node = no_index;  // no_index: the file has none
    std::uint64_t largest_id = 0;               // of any object
    // Names that more than one model of the scene has (Assimp renames all
    // but one of them).
    std::set<std::string> repeated_model_names;
};

// The model hierarchy nests at most this deep below the scene's root
// (Assimp converts it recursively).
inline constexpr std::size_t fbx_max_model_depth = 256;

// Reads and checks the tree: every binary array's exact size; the header's
// FBXVersion; settings; objects' and connections' ids, names and types (as
// Assimp requires them); each instanced mesh's vertices (finite), polygons
// (indices in range, the last one closed), layer elements (arrays of the
// size their mapping says, indices within their data), skin clusters
// (indexes in range, one weight each, finite, 16-number matrices, an
// invertible TransformLink), blend shape channels (shape indexes in range,
// 3 deltas and 3 normals each); the model hierarchy (each model reached
// once from the root, depth bounded).
// Errors name the node and what was wrong; what only degrades the load
// (2-corner polygons, in-between shapes) goes to `report` as warnings.
Status scan_fbx(const FbxDocument& doc, FbxScene& scene, LoadReport& report);

// The "P" entry named `name` of a Properties70 node, or null.
const FbxNode* fbx_p(const FbxDocument& doc, const FbxNode* properties70, std::string_view name);

}  // namespace dfm::mesh
