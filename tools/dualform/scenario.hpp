#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "dualform/dualform.h"
#include "status/tool_status.hpp"

// An edit scenario as docs/scenarios.md defines it, parsed and checked
// for form (types, required fields, unknown fields) but not yet against a
// mesh: vertex indices are checked when the scenario is applied.
namespace dfm::cli {

// A vertex ball: every vertex reachable from `center` along mesh edges
// without leaving the Euclidean ball of radius `radius × diag`.
struct BallSelection {
    std::uint32_t center = 0;
    double radius = 0.0;
};

struct RoiSpec {
    enum class Kind { water_fill, water_fill_clicks, ball, vertices, all };
    Kind kind = Kind::all;
    std::uint32_t first = 0;  // water_fill
    std::uint32_t last = 0;
    dfm_camera camera{};  // water_fill_clicks
    glm::dvec2 first_pixel{0.0};
    glm::dvec2 last_pixel{0.0};
    BallSelection ball;                   // ball
    std::vector<std::uint32_t> vertices;  // vertices
};

struct RotateSpec {
    glm::dvec3 axis{0.0, 0.0, 1.0};
    double degrees = 0.0;
    bool pivot_is_centroid = true;
    glm::dvec3 pivot{0.0};
};

struct HandleSpec {
    // Exactly one selection.
    std::optional<BallSelection> ball;
    std::vector<std::uint32_t> vertices;
    // Motions; none means a fixed anchor. translate is in fractions of diag.
    std::optional<glm::dvec3> translate;
    std::optional<RotateSpec> rotate;
    std::vector<glm::dvec3> targets;  // absolute, one per vertex of `vertices`
};

struct SolverSpec {
    std::optional<double> tolerance;
    std::optional<int> max_iterations;
    std::optional<double> handle_weight;
    std::optional<std::string> method;  // "fitted_rotations" or "paper" (docs/method.md)
};

// The pose a skinned mesh is edited in (docs/skinning.md): an animation of
// the file, by name or index, at a time in seconds.
struct PoseSpec {
    std::optional<std::string> animation_name;
    std::uint32_t animation_index = 0;
    double time = 0.0;
};

struct Scenario {
    std::string mesh;  // as written: a path or model:NAME
    // Loop subdivision steps applied to the mesh after loading (0 to 3): the
    // way scale scenarios make bigger meshes from the real ones. Coarse
    // vertex indices keep their meaning.
    int subdivide = 0;
    std::filesystem::path base_dir;  // the scenario file's folder, for relative paths
    // With a pose, every position of the scenario is in the posed world
    // space; vertex indices stay the file's.
    std::optional<PoseSpec> pose;
    RoiSpec roi;
    std::vector<HandleSpec> handles;
    SolverSpec solver;
};

inline constexpr int max_subdivisions = 3;

// Parses scenario JSON; `source` names it in messages. Errors name the
// source, the line and column, and the field path (e.g.
// "cow.json:7:12: handles[1].rotate.degrees: expected a number").
ToolStatus parse_scenario(std::string_view text, std::string_view source, Scenario& out);

// Parses a CAMERA object on its own, checked as inside a scenario; errors
// are located the same way.
ToolStatus parse_camera(std::string_view text, std::string_view source, dfm_camera& out);

// A --camera argument: CAMERA JSON written inline when its first non-blank
// character is '{', otherwise the path of a file holding it.
ToolStatus read_camera_argument(std::string_view argument, dfm_camera& out);

// Reads and parses a scenario file; base_dir is set to its folder.
ToolStatus load_scenario(const std::filesystem::path& path, Scenario& out);

}  // namespace dfm::cli
