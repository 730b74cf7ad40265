#include "dualform/edit_chain.hpp"

#include "dualform/api_edit.hpp"
#include "dualform/scenario.hpp"

namespace dfm::cli {

namespace {

ToolStatus in_chain(const ToolStatus& s, const std::string& path, std::size_t index,
                    std::size_t count) {
    std::string where = path;
    if (count > 1) {
        where += " (edit ";
        where += std::to_string(index + 1);
        where += " of ";
        where += std::to_string(count);
        where += ")";
    }
    where += ": ";
    where += s.message();
    return ToolStatus(s.code(), where);
}

ToolStatus read_session_positions(dfm_session* session, std::size_t count,
                                  std::vector<glm::dvec3>& out) {
    out.resize(count);
    dfm_vec3_output positions = {};
    positions.data = out.data();
    positions.count = count;
    positions.type = DFM_SCALAR_FLOAT64;
    return api_status(dfm_session_read_positions(session, &positions, nullptr));
}

ToolStatus solve_edit(const Scenario& scenario, ScenarioMesh& mesh, bool last, EditChain& out) {
    ScenarioEdit edit;
    if (ToolStatus s = resolve_scenario_edit(scenario, mesh, edit); !s) return s;
    SessionPtr session;
    if (ToolStatus s = start_session(mesh, edit, session); !s) return s;
    if (ToolStatus s = api_status(dfm_session_solve(session.get(), nullptr)); !s) return s;
    dfm_frame_info solved = {};
    if (ToolStatus s = api_status(dfm_session_poll(session.get(), 0, &solved, nullptr)); !s)
        return s;
    if (solved.status != DFM_OK) {
        return ToolStatus(DFM_ERROR_NUMERICAL, std::string("the solve broke down (") +
                                                   dfm_result_name(solved.status) + ")");
    }
    if (!solved.converged) ++out.unconverged;
    for (std::uint32_t v : edit.roi.vertices) out.marks[v] = mark_roi;
    for (std::size_t g = 0; g < edit.groups.size(); ++g) {
        const HandleSpec& spec = scenario.handles[g];
        const bool anchor = !spec.translate && !spec.rotate && spec.targets.empty();
        for (std::uint32_t v : edit.groups[g]) out.marks[v] = anchor ? mark_anchor : mark_handle;
    }
    if (last) return read_session_positions(session.get(), mesh.info.vertex_count, out.deformed);
    if (ToolStatus s = api_status(dfm_session_bake(session.get())); !s) return s;
    return refresh_scenario_mesh(mesh);
}

}  // namespace

ToolStatus run_edit_chain(std::span<const std::string> scenario_paths, EditChain& out) {
    out = EditChain{};
    if (scenario_paths.empty()) return ToolStatus(DFM_ERROR_INVALID_ARGUMENT, "no scenario given");
    ScenarioMesh mesh;
    std::string mesh_spec;
    const std::size_t count = scenario_paths.size();
    for (std::size_t i = 0; i < count; ++i) {
        const std::string& path = scenario_paths[i];
        Scenario scenario;
        if (ToolStatus s = load_scenario(path, scenario); !s) return s;
        if (i == 0) {
            if (ToolStatus s = open_scenario_mesh(scenario, mesh); !s) return s;
            mesh_spec = scenario.mesh;
            out.rest.positions = mesh.rest;
            if (ToolStatus s = read_mesh_indices(mesh, out.rest.indices); !s) return s;
            out.marks.assign(mesh.info.vertex_count, 0);
        } else if (scenario.mesh != mesh_spec || scenario.subdivide != 0) {
            return in_chain(
                ToolStatus(DFM_ERROR_INVALID_ARGUMENT,
                           "edits in a chain must all name \"" + mesh_spec +
                               "\" without subdivision; this one names \"" + scenario.mesh + "\""),
                path, i, count);
        }
        if (ToolStatus s = solve_edit(scenario, mesh, i + 1 == count, out); !s) {
            return in_chain(s, path, i, count);
        }
    }
    return ToolStatus::ok();
}

}  // namespace dfm::cli
