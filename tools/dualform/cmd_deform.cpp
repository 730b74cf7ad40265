#include <chrono>
#include <cstdio>
#include <string>

#include "deform/deform_session.hpp"
#include "deform/quality.hpp"
#include "dualform/commands.hpp"
#include "dualform/edit_report.hpp"
#include "dualform/edit_setup.hpp"
#include "dualform/file_output.hpp"
#include "dualform/scenario.hpp"
#include "json/json_writer.hpp"
#include "mesh/write.hpp"

namespace dfm::cli {

namespace {

constexpr const char* usage =
    "usage: dualform deform SCENARIO --out MESH [--report JSON] [--roi-out TXT] [--strict]\n"
    "       [--preconditioner cholesky|incomplete_cholesky|jacobi] [--hard-handles]";

}  // namespace

bool parse_preconditioner(std::string_view name, deform::Preconditioner& out) {
    for (auto p : {deform::Preconditioner::cholesky, deform::Preconditioner::incomplete_cholesky,
                   deform::Preconditioner::jacobi}) {
        if (name == deform::preconditioner_name(p)) {
            out = p;
            return true;
        }
    }
    return false;
}

int run_deform(std::span<const std::string_view> args) {
    std::string scenario_path, out_path, report_path, roi_path;
    bool strict = false;
    bool hard = false;
    std::optional<deform::Preconditioner> preconditioner;
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
        } else if (a == "--strict") {
            strict = true;
        } else if (a == "--hard-handles") {
            hard = true;
        } else if (a == "--preconditioner") {
            std::string name;
            deform::Preconditioner p;
            if (!value(name) || !parse_preconditioner(name, p)) {
                return bad_input(
                    "--preconditioner: expected cholesky, incomplete_cholesky or jacobi");
            }
            preconditioner = p;
        } else if (a.starts_with("--") || !scenario_path.empty()) {
            return bad_input(std::string("unexpected argument '") + std::string(a) + "'\n" + usage);
        } else {
            scenario_path = std::string(a);
        }
    }
    if (scenario_path.empty() || out_path.empty()) return bad_input(usage);

    Scenario scenario;
    if (Status s = load_scenario(scenario_path, scenario); !s) return bad_input(s.message());
    const auto start = std::chrono::steady_clock::now();
    deform::MeshModel model;
    if (Status s = load_scenario_model(scenario, model); !s) return bad_input(s.message());
    const auto roi_start = std::chrono::steady_clock::now();
    EditSetup edit;
    if (Status s = resolve_edit(scenario, model, edit); !s) {
        return bad_input(scenario_path + ": " + s.message());
    }
    if (preconditioner) edit.settings.preconditioner = *preconditioner;
    edit.settings.hard_handles = hard;
    std::unique_ptr<deform::DeformSession> session;
    if (Status s = deform::DeformSession::create(model, edit.roi, edit.handle_groups, edit.settings,
                                                 session);
        !s) {
        return bad_input(scenario_path + ": " + s.message());
    }
    const double setup_ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - roi_start)
            .count();
    if (Status s = session->set_targets(edit.targets); !s) return bad_input(s.message());
    deform::SolveReport solved;
    const Status solve_status = session->solve(solved);
    if (!solve_status) {
        std::fprintf(stderr, "error: %s\n", solve_status.message().c_str());
        return exit_failed;
    }
    const deform::QualityReport quality = deform::measure_quality(
        model, session->positions(), edit.in_roi, session->handle_vertices(), session->targets());

    mesh::Mesh result;
    result.positions.assign(session->positions().begin(), session->positions().end());
    result.triangles = model.mesh.triangles;
    if (Status s = mesh::save_mesh(out_path, result); !s) return bad_input(s.message());
    if (!roi_path.empty()) {
        if (Status s = write_index_lines(roi_path, edit.roi); !s) return bad_input(s.message());
    }

    json::JsonWriter json;
    json.begin_object();
    json.key("mesh").value(scenario.mesh);
    json.key("n_vertices").value(std::uint64_t{model.mesh.vertex_count()});
    json.key("n_faces").value(std::uint64_t{model.mesh.face_count()});
    json.key("n_roi").value(std::uint64_t{edit.roi.size()});
    json.key("n_handles").value(std::uint64_t{session->handle_vertices().size()});
    json.key("n_handle_groups").value(std::uint64_t{edit.handle_groups.size()});
    json.key("n_unknowns").value(std::uint64_t{session->setup_report().unknowns});
    json.key("iterations").value(std::uint64_t(solved.iterations));
    json.key("converged").value(solved.converged);
    json.key("last_update").value(solved.last_update);
    json.key("setup_ms").value(setup_ms);
    json.key("solve_ms").value(solved.solve_ms);
    json.key("ms_per_iteration")
        .value(solved.iterations > 0 ? solved.solve_ms / solved.iterations : 0.0);
    json.key("krylov_iterations").value(std::uint64_t{solved.krylov_iterations});
    json.key("linear_residual").value(solved.linear_residual);
    json.key("linear_converged").value(solved.linear_converged);
    json.key("preconditioner").value(deform::preconditioner_name(edit.settings.preconditioner));
    json.key("load_ms").value(std::chrono::duration<double, std::milli>(roi_start - start).count());
    write_quality(json, quality);
    json.end_object();
    std::printf("%s\n", json.str().c_str());
    if (!report_path.empty()) {
        if (Status s = write_text_file(report_path, json.str()); !s) return bad_input(s.message());
    }
    if (strict && !solved.converged) {
        std::fprintf(stderr,
                     "error: did not converge in %d iterations (last update %g of the diagonal)\n",
                     solved.iterations, solved.last_update);
        return exit_failed;
    }
    return exit_ok;
}

}  // namespace dfm::cli
