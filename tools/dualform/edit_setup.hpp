#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "core/status.hpp"
#include "deform/deform_session.hpp"
#include "deform/mesh_model.hpp"
#include "deform/quality.hpp"
#include "dualform/scenario.hpp"
#include "json/json_writer.hpp"
#include "roi/water_fill.hpp"

namespace dfm::cli {

// Reads a preconditioner's name as preconditioner_name() writes it.
bool parse_preconditioner(std::string_view name, deform::Preconditioner& out);

// Writes "quality": {...} from the engine's figures (for the benchmarks of
// internals; the tool's own commands use edit_report.hpp).
void write_quality(json::JsonWriter& json, const deform::QualityReport& q);

// A scenario resolved against its mesh: vertex sets, per-vertex targets and
// solver settings, ready for a DeformSession.
struct EditSetup {
    std::vector<std::uint32_t> roi;  // ascending
    std::vector<std::uint8_t> in_roi;
    std::vector<std::vector<std::uint32_t>> handle_groups;
    std::vector<glm::dvec3> targets;  // one per handle vertex, in group order
    deform::DeformSettings settings;
};

// The ROI the spec selects on the model, ascending. For the Water-Filling
// kinds `diagnosis` receives the fill's diagnosis; otherwise it is reset.
// water_fill_clicks picks both pixels through the camera and fills from the
// picked faces' nearest vertices; a click that hits nothing is an error.
Status resolve_roi(const RoiSpec& spec, const deform::MeshModel& model,
                   std::vector<std::uint32_t>& roi,
                   std::optional<roi::WaterFillDiagnosis>& diagnosis);

Status resolve_edit(const Scenario& scenario, const deform::MeshModel& model, EditSetup& out);

// Loads the scenario's mesh (a path relative to the scenario, or model:NAME)
// and prepares the model.
Status load_scenario_model(const Scenario& scenario, deform::MeshModel& model);

}  // namespace dfm::cli
