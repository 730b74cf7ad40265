#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "dualform/edit_chain.hpp"
#include "status/tool_status.hpp"

namespace dfm::cli {

// What `dualform render` draws: a mesh at rest and, for a scenario, its
// deformed positions and the edit's marks (dfm_vk_mark values).
struct RenderScene {
    MeshArrays rest;
    std::vector<glm::dvec3> deformed;  // empty for a plain mesh
    std::vector<std::uint8_t> marks;   // empty for a plain mesh
};

// Paths ending in .json are scenarios, replayed one after the other (each
// baked before the next, see edit_chain.hpp); anything else is one mesh (a
// path or model:NAME). Errors name the file and what is wrong.
ToolStatus load_render_scene(std::span<const std::string> inputs, RenderScene& out);

}  // namespace dfm::cli
