#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "status/tool_status.hpp"

namespace dfm::cli {

// The renderer's per-vertex marks for an edit (dfm_vk_mark): 1 ROI,
// 2 moving handle, 3 fixed anchor group (0: untouched).
inline constexpr std::uint8_t mark_roi = 1;
inline constexpr std::uint8_t mark_handle = 2;
inline constexpr std::uint8_t mark_anchor = 3;

// A mesh as plain arrays: what the renderer takes.
struct MeshArrays {
    std::vector<glm::dvec3> positions;
    std::vector<std::uint32_t> indices;  // three per triangle

    std::size_t vertex_count() const { return positions.size(); }
};

// Successive edits of one mesh, as the paper's running cow is made: each
// scenario is solved from the pose the previous one left, then baked
// (dfm_session_bake: the next edit's dual Laplacian is measured on it).
// Every scenario must name the same mesh; vertex indices keep their meaning
// since baking keeps the triangles.
struct EditChain {
    MeshArrays rest;                   // the mesh before the first edit
    std::vector<glm::dvec3> deformed;  // after the last
    std::vector<std::uint8_t> marks;   // every edit's, later ones on top
    std::size_t unconverged = 0;       // edits that stopped at their iteration cap
};

// Errors name the scenario file (and its position in the chain).
ToolStatus run_edit_chain(std::span<const std::string> scenario_paths, EditChain& out);

}  // namespace dfm::cli
