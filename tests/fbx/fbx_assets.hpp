#pragma once

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include <glm/vec3.hpp>

#include "mesh/host_mesh.hpp"

// What the FBX tests against the rigged assets share: the assets Blender
// exported as glb and FBX (the rigged_assets fixture, tests/skin/), loads,
// the match between two surfaces by position, the command-line tool,
// Blender's importer (blender_fbx_read.py) and Blender's evaluated meshes.
namespace dfm::test::fbx {

// NAME.glb, NAME.fbx, NAME.frames.json in the fixture's folder.
std::filesystem::path asset(std::string_view file);

struct Loaded {
    mesh::Mesh surface;
    mesh::HostMesh host;
    mesh::LoadReport report;
};

// load_host_mesh; fails the test when the load fails.
Loaded load(const std::filesystem::path& path);

// For each of `a`, the index of the one of `b` nearest to it that no
// earlier one took; fails the test when none is within `tolerance`. The
// largest distance goes to `worst`.
std::vector<std::uint32_t> match_points(const std::vector<glm::dvec3>& a,
                                        const std::vector<glm::dvec3>& b, double tolerance,
                                        double& worst);

// An edit of a mesh given by its host positions: the handle at the vertex
// of largest x, the Water-Filling cut a third of the way from it to the
// centroid.
struct EditVertices {
    std::uint32_t first = 0;
    std::uint32_t last = 0;
};
EditVertices edit_vertices(const std::vector<glm::dvec3>& host);

// A scenario for `mesh` (absolute): Water-Filling from `first` cut at
// `last`, a ball handle at `first` moved by (0, 0.08, 0.05) of the
// diagonal, a tight solve, and `pose` (the scenario key's JSON, or empty);
// written into `dir`, its path returned.
std::string edit_scenario(const std::filesystem::path& dir, const std::filesystem::path& mesh,
                          std::uint32_t first, std::uint32_t last, const std::string& pose = {});

// Runs the dualform tool; fails the test unless it exits 0.
std::string run_cli(const std::vector<std::string>& args);

// python3 tests/fbx/fbx_convert.py MODE IN OUT (MODE --ascii or --7500).
void convert(const std::string& mode, const std::filesystem::path& in,
             const std::filesystem::path& out);

// One object as Blender's FBX importer made it (blender_fbx_read.py).
struct BlenderObject {
    std::string name;
    std::string type;                  // MESH, ARMATURE, ...
    std::vector<glm::dvec3> vertices;  // a mesh's, world space, glTF axes
    struct ShapeKey {
        std::string name;
        double value = 0.0;
        std::vector<glm::dvec3> positions;
    };
    std::vector<ShapeKey> shape_keys;
    std::string armature;            // a mesh's Armature modifier's object
    std::vector<std::string> bones;  // an armature's
    std::vector<glm::dvec3> posed;   // a mesh's evaluated vertices (blender_import's pose)
};
struct BlenderFile {
    std::vector<BlenderObject> objects;
    std::vector<std::string> actions;
    const BlenderObject& object(std::string_view name) const;
};

// Imports each file with Blender's FBX importer, one Blender run; with a
// `pose_frame`, each mesh is also evaluated at that frame of its imported
// action with the shape key `pose_key` at 1 (BlenderObject::posed).
std::vector<BlenderFile> blender_import(const std::vector<std::filesystem::path>& files,
                                        const std::filesystem::path& scratch, int pose_frame = 0,
                                        const std::string& pose_key = {});

// Blender's evaluated mesh of a skinned asset at one frame of one action
// (NAME.frames.json): positions per Blender vertex, glTF axes.
struct Frame {
    std::string animation;
    int frame = 0;
    std::vector<glm::dvec3> positions;
};
std::vector<Frame> blender_frames(std::string_view name, int& fps);

}  // namespace dfm::test::fbx
