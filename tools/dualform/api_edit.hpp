#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include <glm/vec3.hpp>

#include "dualform/c_api.hpp"
#include "dualform/scenario.hpp"
#include "status/tool_status.hpp"

namespace dfm::cli {

// A scenario's mesh through the C API: loaded (a path relative to the
// scenario, or model:NAME) and subdivided as it asks, in a context whose
// sessions solve with `worker_count` threads.
struct ScenarioMesh {
    ContextPtr context;
    MeshPtr mesh;
    dfm_mesh_info info{};
    std::vector<glm::dvec3> rest;  // the rest positions
    // Each vertex's lowest split copy (dfm_mesh_read_surface_map): the
    // index ROI reads give for it.
    std::vector<std::uint32_t> lowest_copy;
};

ToolStatus open_scenario_mesh(const Scenario& scenario, ScenarioMesh& out,
                              std::uint32_t worker_count = 1);

// Reads the info and rest positions again, after a bake.
ToolStatus refresh_scenario_mesh(ScenarioMesh& mesh);

// The triangles' vertex indices, three per triangle.
ToolStatus read_mesh_indices(const ScenarioMesh& mesh, std::vector<std::uint32_t>& out);

// The ROI the spec selects, with its vertices ascending. For the
// Water-Filling kinds `diagnosis` receives the fill's diagnosis; otherwise
// it is reset. Errors name the scenario's field.
struct ScenarioRoi {
    RoiPtr roi;
    std::vector<std::uint32_t> vertices;
    std::optional<dfm_water_fill_diagnosis> diagnosis;
};

ToolStatus select_roi(const RoiSpec& spec, const ScenarioMesh& mesh, ScenarioRoi& out);

// A scenario resolved against its mesh, ready for dfm_session_create: the
// ROI, the handle groups, one target per handle vertex in group order, and
// the solver settings.
struct ScenarioEdit {
    ScenarioRoi roi;
    std::vector<std::vector<std::uint32_t>> groups;
    std::vector<glm::dvec3> targets;
    dfm_solver_settings solver{};

    std::size_t handle_count() const { return targets.size(); }
};

ToolStatus resolve_scenario_edit(const Scenario& scenario, const ScenarioMesh& mesh,
                                 ScenarioEdit& out);

// Creates the edit's session with its targets staged.
ToolStatus start_session(const ScenarioMesh& mesh, const ScenarioEdit& edit, SessionPtr& out);

}  // namespace dfm::cli
