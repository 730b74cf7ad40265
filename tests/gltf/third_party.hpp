#pragma once

#include <filesystem>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

// The real third-party tools the glTF tests check Dualform against: the
// Khronos glTF validator (under node, tests/gltf/validate.mjs) and headless
// Blender (tests/gltf/blender_read.py), and the assets Blender exported
// (the gltf_assets fixture, tests/gltf/make_assets.py).
namespace dfm::test::gltf {

// A file the gltf_assets fixture wrote: "cow.glb", "suzanne.off", ...
std::filesystem::path asset_path(std::string_view name);

struct Validation {
    int exit_code = -1;  // 0: no error, 1: errors, 2: the validator could not run
    std::string report;  // the counts line, then one line per message
};

// Runs the Khronos glTF validator on one .gltf or .glb file.
Validation validate(const std::filesystem::path& file);

// The errors the validator reported ("N errors" of its counts line); fails
// the test when the report has no counts line.
int validation_errors(const Validation& v);

// One mesh object as Blender imported it, positions in glTF axes (+Y up).
struct BlenderObject {
    std::string name;
    std::string mesh;
    std::size_t vertex_count = 0;
    std::vector<double> local;  // x0, y0, z0, x1, ...
    std::vector<double> world;  // after the object's world matrix
    std::vector<std::pair<std::string, std::vector<double>>> shape_keys;  // local, "Basis" first
};

// The mesh objects of each file, imported by one headless Blender run,
// sorted by object name; Blender's JSON goes into the folder `scratch`
// (the caller's own: tests may run at the same time).
std::vector<std::vector<BlenderObject>> blender_read(
    const std::vector<std::filesystem::path>& files, const std::filesystem::path& scratch);

// The object named `name`; fails the test when absent.
const BlenderObject& blender_object(const std::vector<BlenderObject>& objects,
                                    std::string_view name);

}  // namespace dfm::test::gltf
