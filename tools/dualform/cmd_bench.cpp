#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <initializer_list>
#include <memory>
#include <numeric>
#include <optional>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "deform/deform_session.hpp"
#include "deform/quality.hpp"
#include "dualform/commands.hpp"
#include "dualform/edit_report.hpp"
#include "dualform/edit_setup.hpp"
#include "dualform/file_output.hpp"
#include "dualform/scenario.hpp"
#include "json/json_writer.hpp"
#include "solver/thread_pool.hpp"

// Benchmarks scenarios: set-up and the solve from rest, repeated, then a
// warm drag of 60 frames, each solved to tolerance from the previous frame.
namespace dfm::cli {

namespace {

constexpr const char* usage =
    "usage: dualform bench SCENARIO... [--repeat N] [--json FILE]\n"
    "       [--preconditioner cholesky|incomplete_cholesky|jacobi] [--workers N]\n"
    "       [--no-prediction] [--tolerance T]";
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

double median(std::vector<double> values) {
    std::sort(values.begin(), values.end());
    return values[values.size() / 2];
}

// The parts of set-up, and of an outer iteration (ms per iteration), one
// sample per run or frame.
struct SetupParts {
    std::vector<double> rows, assembly, ordering, symbolic, numeric;

    void add(const deform::SetupReport& r) {
        rows.push_back(r.rows_ms);
        assembly.push_back(r.assembly_ms);
        ordering.push_back(r.ordering_ms);
        symbolic.push_back(r.symbolic_ms);
        numeric.push_back(r.numeric_ms);
    }
};

struct IterationParts {
    std::vector<double> linear, rhs, normals, anderson;

    void add(const deform::SolveReport& r) {
        const double per = 1.0 / std::max(1, r.iterations);
        linear.push_back(r.linear_ms * per);
        rhs.push_back(r.rhs_ms * per);
        normals.push_back(r.normals_ms * per);
        anderson.push_back(r.anderson_ms * per);
    }
};

void write_medians(
    json::JsonWriter& json, std::string_view key,
    std::initializer_list<std::pair<std::string_view, const std::vector<double>*>> parts) {
    json.key(key).begin_object();
    for (const auto& [name, values] : parts) json.key(name).value(median(*values));
    json.end_object();
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

// What the command line changes in every scenario's settings.
struct Overrides {
    std::optional<deform::Preconditioner> preconditioner;
    solver::ThreadPool* pool = nullptr;
    bool predict_frames = true;
    std::optional<double> tolerance;
};

Status bench_scenario(const std::string& path, int repeat, const Overrides& overrides,
                      json::JsonWriter& json) {
    Scenario scenario;
    if (Status s = load_scenario(path, scenario); !s) return s;
    deform::MeshModel model;
    if (Status s = load_scenario_model(scenario, model); !s) return s;
    EditSetup edit;
    if (Status s = resolve_edit(scenario, model, edit); !s)
        return Status(s.code(), path + ": " + s.message());
    if (overrides.preconditioner) edit.settings.preconditioner = *overrides.preconditioner;
    edit.settings.pool = overrides.pool;
    edit.settings.predict_frames = overrides.predict_frames;
    if (overrides.tolerance) edit.settings.tolerance = *overrides.tolerance;

    std::vector<double> setup, solve, per_iteration;
    SetupParts setup_parts;
    IterationParts solve_parts;
    Run run;
    for (int r = 0; r < repeat; ++r) {
        if (Status s = run_once(model, edit, run); !s)
            return Status(s.code(), path + ": " + s.message());
        setup.push_back(run.setup_ms);
        solve.push_back(run.solve.solve_ms);
        per_iteration.push_back(run.solve.solve_ms / std::max(1, run.solve.iterations));
        setup_parts.add(run.session->setup_report());
        solve_parts.add(run.solve);
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
    IterationParts frame_parts;
    int unconverged = 0;
    int predicted = 0;
    for (int f = 1; f <= drag_frames; ++f) {
        const double t = static_cast<double>(f) / drag_frames;
        for (std::size_t h = 0; h < start.size(); ++h)
            frame_targets[h] = start[h] + t * (edit.targets[h] - start[h]);
        if (Status s = drag->set_targets(frame_targets); !s) return s;
        deform::SolveReport frame;
        if (Status s = drag->solve(frame); !s) return s;
        frame_ms.push_back(frame.solve_ms);
        frame_iterations.push_back(frame.iterations);
        frame_parts.add(frame);
        unconverged += frame.converged ? 0 : 1;
        predicted += frame.predicted ? 1 : 0;
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
    json.key("workers").value(
        std::uint64_t{overrides.pool != nullptr ? overrides.pool->thread_count() : 1});
    json.key("frame_prediction").value(overrides.predict_frames);
    json.key("tolerance").value(edit.settings.tolerance);
    write_spread(json, "setup_ms", setup);
    write_medians(json, "setup_parts_ms",
                  {{"rows", &setup_parts.rows},
                   {"assembly", &setup_parts.assembly},
                   {"ordering", &setup_parts.ordering},
                   {"symbolic", &setup_parts.symbolic},
                   {"numeric", &setup_parts.numeric}});
    write_spread(json, "solve_ms", solve);
    write_spread(json, "ms_per_iteration", per_iteration);
    write_medians(json, "iteration_parts_ms",
                  {{"linear_solve", &solve_parts.linear},
                   {"right_hand_side", &solve_parts.rhs},
                   {"normals", &solve_parts.normals},
                   {"anderson", &solve_parts.anderson}});
    json.key("iterations").value(std::uint64_t(solved.iterations));
    json.key("converged").value(solved.converged);
    json.key("krylov_iterations").value(std::uint64_t{solved.krylov_iterations});
    json.key("drag").begin_object();
    json.key("frames").value(std::uint64_t{drag_frames});
    json.key("unconverged_frames").value(std::uint64_t(unconverged));
    json.key("predicted_frames").value(std::uint64_t(predicted));
    json.key("iterations")
        .value(
            std::uint64_t(std::accumulate(frame_iterations.begin(), frame_iterations.end(), 0.0)));
    write_spread(json, "frame_ms", frame_ms);
    write_spread(json, "iterations_per_frame", frame_iterations);
    write_medians(json, "iteration_parts_ms",
                  {{"linear_solve", &frame_parts.linear},
                   {"right_hand_side", &frame_parts.rhs},
                   {"normals", &frame_parts.normals},
                   {"anderson", &frame_parts.anderson}});
    json.end_object();
    write_quality(json, quality);
    json.key("peak_rss_mib").value(peak_rss_mib());
    json.end_object();
    std::fprintf(stderr,
                 "%-28s setup %8.2f (rows %.2f assembly %.2f ordering %.2f symbolic %.2f "
                 "numeric %.2f) | iteration %.3f (solve %.3f rhs %.3f normals %.3f anderson "
                 "%.3f) | drag frame %.2f, %.0f iterations\n",
                 path.c_str(), median(setup), median(setup_parts.rows),
                 median(setup_parts.assembly), median(setup_parts.ordering),
                 median(setup_parts.symbolic), median(setup_parts.numeric), median(per_iteration),
                 median(solve_parts.linear), median(solve_parts.rhs), median(solve_parts.normals),
                 median(solve_parts.anderson), median(frame_ms), median(frame_iterations));
    return Status::ok();
}

}  // namespace

int run_bench(std::span<const std::string_view> args) {
    std::vector<std::string> scenarios;
    std::string json_path;
    int repeat = 5;
    int workers = 1;
    Overrides overrides;
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
            overrides.preconditioner = p;
        } else if (a == "--workers") {
            if (i + 1 >= args.size()) return bad_input("--workers needs a count");
            try {
                workers = std::stoi(std::string(args[++i]));
            } catch (const std::exception&) {
                workers = 0;
            }
            if (workers < 1 || workers > 64) return bad_input("--workers: expected 1 to 64");
        } else if (a == "--tolerance") {
            double t = 0.0;
            try {
                t = i + 1 < args.size() ? std::stod(std::string(args[++i])) : 0.0;
            } catch (const std::exception&) {
                t = 0.0;
            }
            if (!(t > 0.0) || !std::isfinite(t))
                return bad_input("--tolerance: expected a positive number");
            overrides.tolerance = t;
        } else if (a == "--no-prediction") {
            overrides.predict_frames = false;
        } else if (a.starts_with("--")) {
            return bad_input(std::string("unknown option '") + std::string(a) + "'\n" + usage);
        } else {
            scenarios.emplace_back(a);
        }
    }
    if (scenarios.empty()) return bad_input(usage);
    std::unique_ptr<solver::ThreadPool> pool;
    if (workers > 1) {
        pool = std::make_unique<solver::ThreadPool>(static_cast<std::size_t>(workers));
        overrides.pool = pool.get();
    }

    json::JsonWriter json;
    json.begin_object();
    json.key("machine").begin_object();
    json.key("hardware_threads").value(std::uint64_t{std::thread::hardware_concurrency()});
    json.end_object();
    json.key("results").begin_array();
    for (const std::string& path : scenarios) {
        if (Status s = bench_scenario(path, repeat, overrides, json); !s)
            return bad_input(s.message());
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
