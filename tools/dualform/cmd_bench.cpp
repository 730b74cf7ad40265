#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <string>
#include <thread>
#include <vector>

#include "deform/deform_session.hpp"
#include "deform/quality.hpp"
#include "dualform/commands.hpp"
#include "dualform/edit_report.hpp"
#include "dualform/edit_setup.hpp"
#include "dualform/file_output.hpp"
#include "dualform/scenario.hpp"
#include "json/json_writer.hpp"

// Benchmarks scenarios: set-up and the solve from rest, repeated, then a
// warm drag of 60 frames, each solved to tolerance from the previous frame.
namespace dfm::cli {

namespace {

constexpr const char* usage =
    "usage: dualform bench SCENARIO... [--repeat N] [--json FILE]\n"
    "       [--preconditioner cholesky|incomplete_cholesky|jacobi]";
constexpr int drag_frames = 60;

using Clock = std::chrono::steady_clock;

double ms_since(Clock::time_point t) {
    return std::chrono::duration<double, std::milli>(Clock::now() - t).count();
}

void write_spread(json::JsonWriter& json, std::string_view key, std::vector<double> values) {
    std::sort(values.begin(), values.end());
    const auto at = [&](double q) {
        return values[static_cast<std::size_t>(q * static_cast<double>(values.size() - 1) + 0.5)];
    };
    json.key(key).begin_object();
    json.key("median").value(at(0.5));
    json.key("min").value(values.front());
    json.key("p90").value(at(0.9));
    json.key("max").value(values.back());
    json.end_object();
}

double peak_rss_mib() {
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    return static_cast<double>(usage.ru_maxrss) / 1024.0;
}

struct Run {
    std::unique_ptr<deform::DeformSession> session;
    deform::SolveReport solve;
    double setup_ms = 0.0;
};

Status run_once(const deform::MeshModel& model, const EditSetup& edit, Run& run) {
    run.session.reset();  // one session at a time, so the peak memory is one edit's
    const auto t0 = Clock::now();
    if (Status s = deform::DeformSession::create(model, edit.roi, edit.handle_groups, edit.settings,
                                                 run.session);
        !s) {
        return s;
    }
    run.setup_ms = ms_since(t0);
    if (Status s = run.session->set_targets(edit.targets); !s) return s;
    return run.session->solve(run.solve);
}

Status bench_scenario(const std::string& path, int repeat, std::optional<deform::Preconditioner> pc,
                      json::JsonWriter& json) {
    Scenario scenario;
    if (Status s = load_scenario(path, scenario); !s) return s;
    deform::MeshModel model;
    if (Status s = load_scenario_model(scenario, model); !s) return s;
    EditSetup edit;
    if (Status s = resolve_edit(scenario, model, edit); !s)
        return Status(s.code(), path + ": " + s.message());
    if (pc) edit.settings.preconditioner = *pc;

    std::vector<double> setup, solve, per_iteration;
    Run run;
    for (int r = 0; r < repeat; ++r) {
        if (Status s = run_once(model, edit, run); !s)
            return Status(s.code(), path + ": " + s.message());
        setup.push_back(run.setup_ms);
        solve.push_back(run.solve.solve_ms);
        per_iteration.push_back(run.solve.solve_ms / std::max(1, run.solve.iterations));
    }
    const deform::QualityReport quality =
        deform::measure_quality(model, run.session->positions(), edit.in_roi,
                                run.session->handle_vertices(), run.session->targets());

    const deform::SetupReport setup_report = run.session->setup_report();
    const deform::SolveReport solved = run.solve;
    run.session.reset();

    // The drag: a fresh session, targets moved from rest to the scenario's
    // in equal steps, each frame warm-started from the last.
    std::unique_ptr<deform::DeformSession> drag;
    if (Status s =
            deform::DeformSession::create(model, edit.roi, edit.handle_groups, edit.settings, drag);
        !s) {
        return s;
    }
    std::vector<glm::dvec3> start(drag->targets().begin(), drag->targets().end());
    std::vector<glm::dvec3> frame_targets(start.size());
    std::vector<double> frame_ms;
    std::vector<double> frame_iterations;
    int unconverged = 0;
    for (int f = 1; f <= drag_frames; ++f) {
        const double t = static_cast<double>(f) / drag_frames;
        for (std::size_t h = 0; h < start.size(); ++h)
            frame_targets[h] = start[h] + t * (edit.targets[h] - start[h]);
        if (Status s = drag->set_targets(frame_targets); !s) return s;
        deform::SolveReport frame;
        if (Status s = drag->solve(frame); !s) return s;
        frame_ms.push_back(frame.solve_ms);
        frame_iterations.push_back(frame.iterations);
        unconverged += frame.converged ? 0 : 1;
    }

    const deform::SetupReport& sr = setup_report;
    json.begin_object();
    json.key("scenario").value(path);
    json.key("mesh").value(scenario.mesh);
    json.key("n_vertices").value(std::uint64_t{model.mesh.vertex_count()});
    json.key("n_roi").value(std::uint64_t{edit.roi.size()});
    json.key("n_unknowns").value(std::uint64_t{sr.unknowns});
    json.key("n_rows").value(std::uint64_t{sr.rows});
    json.key("normal_nonzeros").value(std::uint64_t{sr.normal_nonzeros});
    json.key("preconditioner").value(deform::preconditioner_name(edit.settings.preconditioner));
    json.key("repeat").value(std::uint64_t(repeat));
    write_spread(json, "setup_ms", setup);
    write_spread(json, "solve_ms", solve);
    write_spread(json, "ms_per_iteration", per_iteration);
    json.key("iterations").value(std::uint64_t(solved.iterations));
    json.key("converged").value(solved.converged);
    json.key("krylov_iterations").value(std::uint64_t{solved.krylov_iterations});
    json.key("drag").begin_object();
    json.key("frames").value(std::uint64_t{drag_frames});
    json.key("unconverged_frames").value(std::uint64_t(unconverged));
    write_spread(json, "frame_ms", frame_ms);
    write_spread(json, "iterations_per_frame", frame_iterations);
    json.end_object();
    write_quality(json, quality);
    json.key("peak_rss_mib").value(peak_rss_mib());
    json.end_object();
    return Status::ok();
}

}  // namespace

int run_bench(std::span<const std::string_view> args) {
    std::vector<std::string> scenarios;
    std::string json_path;
    int repeat = 5;
    std::optional<deform::Preconditioner> pc;
    for (std::size_t i = 0; i < args.size(); ++i) {
        const std::string_view a = args[i];
        if (a == "--repeat") {
            if (i + 1 >= args.size()) return bad_input("--repeat needs a count");
            try {
                repeat = std::stoi(std::string(args[++i]));
            } catch (const std::exception&) {
                repeat = 0;
            }
            if (repeat < 1 || repeat > 1000) return bad_input("--repeat: expected 1 to 1000");
        } else if (a == "--json") {
            if (i + 1 >= args.size()) return bad_input("--json needs a path");
            json_path = std::string(args[++i]);
        } else if (a == "--preconditioner") {
            deform::Preconditioner p;
            if (i + 1 >= args.size() || !parse_preconditioner(args[++i], p)) {
                return bad_input(
                    "--preconditioner: expected cholesky, incomplete_cholesky or jacobi");
            }
            pc = p;
        } else if (a.starts_with("--")) {
            return bad_input(std::string("unknown option '") + std::string(a) + "'\n" + usage);
        } else {
            scenarios.emplace_back(a);
        }
    }
    if (scenarios.empty()) return bad_input(usage);

    json::JsonWriter json;
    json.begin_object();
    json.key("machine").begin_object();
    json.key("hardware_threads").value(std::uint64_t{std::thread::hardware_concurrency()});
    json.end_object();
    json.key("results").begin_array();
    for (const std::string& path : scenarios) {
        if (Status s = bench_scenario(path, repeat, pc, json); !s) return bad_input(s.message());
        std::fprintf(stderr, "bench: %s done\n", path.c_str());
    }
    json.end_array();
    json.end_object();
    std::printf("%s\n", json.str().c_str());
    if (!json_path.empty()) {
        if (Status s = write_text_file(json_path, json.str()); !s) return bad_input(s.message());
    }
    return exit_ok;
}

}  // namespace dfm::cli
