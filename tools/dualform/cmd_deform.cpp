#include <chrono>
#include <cstdio>
#include <optional>
#include <string>
#include <vector>

#include "dualform/api_edit.hpp"
#include "dualform/commands.hpp"
#include "dualform/edit_report.hpp"
#include "dualform/file_output.hpp"
#include "dualform/scenario.hpp"
#include "dualform/usage.hpp"
#include "json/json_writer.hpp"

namespace dfm::cli {

namespace {

double ms_since(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
        .count();
}

// The solved shape becomes the scenario mesh's rest pose (the report is
// measured by then), so that a mesh from glTF is written back into its own
// asset; `morph_target` non-empty writes the edit as a morph target instead.
ToolStatus save_result(const ScenarioMesh& mesh, dfm_session* session, const std::string& path,
                       const std::string& morph_target) {
    std::vector<double> positions(3 * mesh.info.vertex_count);
    dfm_vec3_output out = {};
    out.data = positions.data();
    out.count = mesh.info.vertex_count;
    out.type = DFM_SCALAR_FLOAT64;
    if (ToolStatus s = api_status(dfm_session_read_positions(session, &out, nullptr)); !s) return s;
    dfm_vec3_input in = {};
    in.data = positions.data();
    in.count = mesh.info.vertex_count;
    in.type = DFM_SCALAR_FLOAT64;
    if (ToolStatus s = api_status(dfm_mesh_set_positions(mesh.mesh.get(), &in)); !s) return s;
    dfm_save_options options = {};
    options.struct_size = sizeof options;
    options.morph_target_name = morph_target.empty() ? nullptr : morph_target.c_str();
    return api_status(dfm_mesh_save_with_options(mesh.mesh.get(), path.c_str(), &options));
}

}  // namespace

int run_deform(std::span<const std::string_view> args) {
    std::string scenario_path, out_path, report_path, roi_path, morph_target;
    bool strict = false;
    bool hard = false;
    std::optional<dfm_method> method;
    for (std::size_t i = 0; i < args.size(); ++i) {
        const std::string_view a = args[i];
        auto value = [&](std::string& into) {
            if (i + 1 >= args.size()) return false;
            into = std::string(args[++i]);
            return true;
        };
        if (a == "--out") {
            if (!value(out_path)) return bad_input("--out needs a path");
        } else if (a == "--report") {
            if (!value(report_path)) return bad_input("--report needs a path");
        } else if (a == "--roi-out") {
            if (!value(roi_path)) return bad_input("--roi-out needs a path");
        } else if (a == "--morph-target") {
            if (!value(morph_target) || morph_target.empty()) {
                return bad_input("--morph-target needs a name");
            }
        } else if (a == "--strict") {
            strict = true;
        } else if (a == "--hard-handles") {
            hard = true;
        } else if (a == "--method") {
            std::string name;
            if (!value(name) || (name != "fitted_rotations" && name != "paper")) {
                return bad_input("--method: expected fitted_rotations or paper");
            }
            method = name == "paper" ? DFM_METHOD_PAPER : DFM_METHOD_FITTED_ROTATIONS;
        } else if (a.starts_with("--") || !scenario_path.empty()) {
            return bad_input(std::string("unexpected argument '") + std::string(a) + "'\n" +
                             usage(deform_help));
        } else {
            scenario_path = std::string(a);
        }
    }
    if (scenario_path.empty() || out_path.empty()) return bad_input(usage(deform_help));

    Scenario scenario;
    if (ToolStatus s = load_scenario(scenario_path, scenario); !s) return bad_input(s.message());
    const auto start = std::chrono::steady_clock::now();
    ScenarioMesh mesh;
    if (ToolStatus s = open_scenario_mesh(scenario, mesh); !s) return bad_input(s.message());
    const double load_ms = ms_since(start);
    const auto setup_start = std::chrono::steady_clock::now();
    ScenarioEdit edit;
    if (ToolStatus s = resolve_scenario_edit(scenario, mesh, edit); !s) {
        return bad_input(scenario_path + ": " + s.message());
    }
    edit.solver.hard_handles = hard;
    if (method) edit.solver.method = *method;
    SessionPtr session;
    if (ToolStatus s = start_session(mesh, edit, session); !s) {
        return work_failure(ToolStatus(s.code(), scenario_path + ": " + s.message()));
    }
    const double setup_ms = ms_since(setup_start);

    // Solved on this thread: the result is bit for bit the worker's.
    dfm_frame_info solved = {};
    if (ToolStatus s = api_status(dfm_session_solve(session.get(), nullptr)); !s) {
        return failed(s.message());
    }
    dfm_quality quality = {};
    if (ToolStatus s = api_status(dfm_session_measure_quality(session.get(), &quality, &solved));
        !s) {
        return failed(s.message());
    }
    if (solved.status != DFM_OK) {
        return failed(std::string("the solve broke down (") + dfm_result_name(solved.status) + ")");
    }
    dfm_solve_report solver = {};
    if (ToolStatus s = api_status(dfm_session_get_solve_report(session.get(), &solver, nullptr));
        !s) {
        return failed(s.message());
    }

    if (ToolStatus s = save_result(mesh, session.get(), out_path, morph_target); !s) {
        return work_failure(s);
    }
    if (!roi_path.empty()) {
        if (ToolStatus s = write_index_lines(roi_path, edit.roi.vertices); !s) {
            return work_failure(s);
        }
    }

    json::JsonWriter json;
    json.begin_object();
    json.field("mesh", scenario.mesh);
    json.field("n_vertices", mesh.info.vertex_count);
    json.field("n_faces", mesh.info.triangle_count);
    json.field("n_roi", edit.roi.vertices.size());
    json.field("n_handles", edit.handle_count());
    json.field("n_handle_groups", edit.groups.size());
    json.field("n_unknowns", solver.unknowns);
    json.field("method", edit.solver.method == DFM_METHOD_PAPER ? "paper" : "fitted_rotations");
    json.field("iterations", solved.iterations);
    json.field("converged", solved.converged);
    json.field("last_update", solved.last_update);
    json.field("setup_ms", setup_ms);
    json.field("solve_ms", solved.solve_ms);
    json.field("ms_per_iteration",
               solved.iterations > 0 ? solved.solve_ms / solved.iterations : 0.0);
    json.field("krylov_iterations", solver.krylov_iterations);
    json.field("linear_residual", solver.linear_residual);
    json.field("linear_converged", solver.linear_converged);
    json.field("load_ms", load_ms);
    write_quality(json, quality);
    if (scenario.pose) {
        dfm_skin_info skin = {};
        if (ToolStatus s = api_status(dfm_mesh_get_skin_info(mesh.mesh.get(), &skin)); !s) {
            return failed(s.message());
        }
        dfm_animation_info animation = {};
        if (ToolStatus s = api_status(dfm_mesh_get_animation_info(
                mesh.mesh.get(), static_cast<std::uint32_t>(skin.pose_animation), &animation));
            !s) {
            return failed(s.message());
        }
        json.key("pose").begin_object();
        json.field("animation", animation.name);
        json.field("time", skin.pose_time);
        json.end_object();
        json.key("corrective").begin_object();
        json.field("vertices", skin.corrective_vertex_count);
        json.field("worst_condition", skin.corrective_worst_condition);
        json.field("damped", skin.corrective_damped_count);
        json.end_object();
    }
    json.end_object();
    std::printf("%s\n", json.str().c_str());
    if (!report_path.empty()) {
        if (ToolStatus s = write_text_file(report_path, json.str()); !s) return work_failure(s);
    }
    if (strict && !solved.converged) {
        std::fprintf(stderr,
                     "error: did not converge in %u iterations (last update %g of the diagonal)\n",
                     solved.iterations, solved.last_update);
        return exit_failed;
    }
    return exit_ok;
}

}  // namespace dfm::cli
