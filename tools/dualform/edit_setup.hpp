#pragma once

#include <cstdint>
#include <vector>

#include "core/status.hpp"
#include "deform/deform_session.hpp"
#include "deform/mesh_model.hpp"
#include "dualform/scenario.hpp"

namespace dfm::cli {

// A scenario resolved against its mesh: vertex sets, per-vertex targets and
// solver settings, ready for a DeformSession.
struct EditSetup {
    std::vector<std::uint32_t> roi;  // ascending
    std::vector<std::uint8_t> in_roi;
    std::vector<std::vector<std::uint32_t>> handle_groups;
    std::vector<glm::dvec3> targets;  // one per handle vertex, in group order
    deform::DeformSettings settings;
};

Status resolve_edit(const Scenario& scenario, const deform::MeshModel& model, EditSetup& out);

// Loads the scenario's mesh (a path relative to the scenario, or model:NAME)
// and prepares the model.
Status load_scenario_model(const Scenario& scenario, deform::MeshModel& model);

}  // namespace dfm::cli
