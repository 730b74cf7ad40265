#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <initializer_list>
#include <iterator>
#include <numeric>
#include <optional>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "dualform/api_edit.hpp"
#include "dualform/c_api.hpp"
#include "dualform/commands.hpp"
#include "dualform/edit_report.hpp"
#include "dualform/file_output.hpp"
#include "dualform/scenario.hpp"
#include "dualform/usage.hpp"
#include "json/json_writer.hpp"

// Benchmarks scenarios: set-up and the solve from rest, repeated, then a
// warm drag of 60 frames, each solved to tolerance from the previous frame.
namespace dfm::cli {

namespace {

constexpr int drag_frames = 60;

using Clock = std::chrono::steady_clock;

// The value at fraction q of the sorted values (the nearest rank).
double at_rank(const std::vector<double>& sorted, double q) {
    return sorted[static_cast<std::size_t>(q * static_cast<double>(sorted.size() - 1) + 0.5)];
}

double percentile(std::vector<double> values, double q) {
    std::sort(values.begin(), values.end());
    return at_rank(values, q);
}

void write_spread(json::JsonWriter& json, std::string_view key, std::vector<double> values) {
    std::sort(values.begin(), values.end());
    const auto at = [&](double q) { return at_rank(values, q); };
    json.key(key).begin_object();
    json.key("median").value(at(0.5));
    json.key("min").value(values.front());
    json.key("p90").value(at(0.9));
    json.key("p99").value(at(0.99));
    json.key("max").value(values.back());
    json.end_object();
}

double peak_rss_mib() {
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    return static_cast<double>(usage.ru_maxrss) / 1024.0;
}

double median(std::vector<double> values) {
    return percentile(std::move(values), 0.5);
}

// The parts of set-up, and of an outer iteration (ms per iteration), one
// sample per run or frame.
struct SetupParts {
    std::vector<double> rows, assembly, ordering, symbolic, numeric;

    void add(const dfm_solve_details& d) {
        rows.push_back(d.setup_rows_ms);
        assembly.push_back(d.setup_assembly_ms);
        ordering.push_back(d.setup_ordering_ms);
        symbolic.push_back(d.setup_symbolic_ms);
        numeric.push_back(d.setup_numeric_ms);
    }
};

struct IterationParts {
    std::vector<double> linear, rhs, normals, anderson;

    void add(const dfm_solve_details& d, std::uint32_t iterations) {
        const double per = 1.0 / std::max(1u, iterations);
        linear.push_back(d.linear_solve_ms * per);
        rhs.push_back(d.right_hand_side_ms * per);
        normals.push_back(d.normals_ms * per);
        anderson.push_back(d.anderson_ms * per);
    }
};

void write_medians(
    json::JsonWriter& json, std::string_view key,
    std::initializer_list<std::pair<std::string_view, const std::vector<double>*>> parts) {
    json.key(key).begin_object();
    for (const auto& [name, values] : parts) json.key(name).value(median(*values));
    json.end_object();
}

// A solved frame as the reports give it.
struct Solved {
    dfm_frame_info info{};
    dfm_solve_report report{};
    dfm_solve_details details{};
};

ToolStatus solve_frame(dfm_session* session, Solved& out) {
    if (ToolStatus s = api_status(dfm_session_solve(session, nullptr)); !s) return s;
    if (ToolStatus s = api_status(dfm_session_get_solve_report(session, &out.report, &out.info));
        !s)
        return s;
    out.details = dfm_solve_details{};
    out.details.struct_size = sizeof out.details;
    if (ToolStatus s = api_status(dfm_session_get_solve_details(session, &out.details, nullptr));
        !s)
        return s;
    if (out.info.status != DFM_OK) {
        return ToolStatus(DFM_ERROR_NUMERICAL, std::string("the solve broke down (") +
                                                   dfm_result_name(out.info.status) + ")");
    }
    return ToolStatus::ok();
}

ToolStatus set_targets(dfm_session* session, const std::vector<glm::dvec3>& targets) {
    dfm_vec3_input input = {};
    input.data = targets.data();
    input.count = targets.size();
    input.type = DFM_SCALAR_FLOAT64;
    return api_status(dfm_session_set_targets(session, &input));
}

double ms_since(Clock::time_point start) {
    return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

// A posed scenario's costs, one sample each a call (ms).
struct PoseTimes {
    std::vector<double> set_pose;     // dfm_mesh_set_pose_animation
    std::vector<double> read;         // dfm_mesh_read_positions after it
    std::vector<double> posed_model;  // the first call that needs the posed model
    std::vector<double> bake;         // dfm_mesh_set_positions in the pose
};

// Posing a posed scenario's mesh: dfm_mesh_set_pose_animation at times
// across its animation (100 calls a repeat); after the last of each repeat
// a read of the posed positions, then dfm_roi_all, the first call that
// needs the posed model (its dual Laplacian); and `repeat` bakes of the
// drag's last frame (the corrective and the models), each undone. The
// scenario's pose is set again at the end.
ToolStatus time_pose(const ScenarioMesh& mesh, dfm_session* drag, int repeat, PoseTimes& times) {
    dfm_mesh* m = mesh.mesh.get();
    dfm_skin_info skin = {};
    if (ToolStatus s = api_status(dfm_mesh_get_skin_info(m, &skin)); !s) return s;
    const auto animation = static_cast<std::uint32_t>(skin.pose_animation);
    const double scenario_time = skin.pose_time;
    dfm_animation_info info = {};
    if (ToolStatus s = api_status(dfm_mesh_get_animation_info(m, animation, &info)); !s) return s;
    std::vector<double> positions(3 * mesh.info.vertex_count);
    dfm_vec3_output out = {positions.data(), mesh.info.vertex_count, 0, DFM_SCALAR_FLOAT64};
    constexpr int calls = 100;
    for (int r = 0; r < repeat; ++r) {
        for (int c = 0; c < calls; ++c) {
            const double t = info.start + (info.end - info.start) * c / (calls - 1);
            const auto start = Clock::now();
            if (ToolStatus s = api_status(dfm_mesh_set_pose_animation(m, animation, t)); !s)
                return s;
            times.set_pose.push_back(ms_since(start));
        }
        auto start = Clock::now();
        if (ToolStatus s = api_status(dfm_mesh_read_positions(m, &out)); !s) return s;
        times.read.push_back(ms_since(start));
        start = Clock::now();
        dfm_roi* all = nullptr;
        if (ToolStatus s = api_status(dfm_roi_all(m, &all)); !s) return s;
        times.posed_model.push_back(ms_since(start));
        dfm_roi_destroy(all);
    }
    if (ToolStatus s = api_status(dfm_mesh_set_pose_animation(m, animation, scenario_time)); !s)
        return s;
    if (ToolStatus s = api_status(dfm_session_read_positions(drag, &out, nullptr)); !s) return s;
    const dfm_vec3_input in = {positions.data(), mesh.info.vertex_count, 0, DFM_SCALAR_FLOAT64};
    for (int r = 0; r < repeat; ++r) {
        const auto start = Clock::now();
        if (ToolStatus s = api_status(dfm_mesh_set_positions(m, &in)); !s) return s;
        times.bake.push_back(ms_since(start));
        if (ToolStatus s = api_status(dfm_mesh_undo_bake(m)); !s) return s;
    }
    return ToolStatus::ok();
}

// What the command line changes in every scenario's settings.
struct Overrides {
    std::optional<dfm_preconditioner> preconditioner;
    std::uint32_t workers = 1;
    bool predict_frames = true;
    std::optional<double> tolerance;
};

struct PreconditionerName {
    dfm_preconditioner value;
    const char* name;
};

constexpr PreconditionerName preconditioner_names[] = {
    {DFM_PRECONDITIONER_CHOLESKY, "cholesky"},
    {DFM_PRECONDITIONER_INCOMPLETE_CHOLESKY, "incomplete_cholesky"},
    {DFM_PRECONDITIONER_JACOBI, "jacobi"},
};

const char* preconditioner_name(dfm_preconditioner p) {
    for (const PreconditionerName& n : preconditioner_names) {
        if (n.value == p) return n.name;
    }
    return preconditioner_names[0].name;  // DFM_PRECONDITIONER_DEFAULT
}

// dfm_solver_settings.tolerance's default, for the report of a scenario that sets none.
constexpr double default_tolerance = 1e-5;

// A scenario as the bench runs it: the document, its mesh and its edit with
// the command line's overrides.
struct BenchInput {
    Scenario scenario;
    ScenarioMesh mesh;
    ScenarioEdit edit;
};

// The input side: what fails here is bad input.
ToolStatus read_bench_input(const std::string& path, const Overrides& overrides, BenchInput& in) {
    if (ToolStatus s = load_scenario(path, in.scenario); !s) return s;
    if (ToolStatus s = open_scenario_mesh(in.scenario, in.mesh, overrides.workers); !s) return s;
    if (ToolStatus s = resolve_scenario_edit(in.scenario, in.mesh, in.edit); !s)
        return ToolStatus(s.code(), path + ": " + s.message());
    if (overrides.preconditioner) in.edit.solver.preconditioner = *overrides.preconditioner;
    in.edit.solver.disable_prediction = !overrides.predict_frames;
    if (overrides.tolerance) in.edit.solver.tolerance = *overrides.tolerance;
    return ToolStatus::ok();
}

// The work: set-ups, solves from rest and the drag, timed, into `json`.
ToolStatus bench_scenario(const std::string& path, const BenchInput& in, int repeat,
                          const Overrides& overrides, json::JsonWriter& json) {
    const Scenario& scenario = in.scenario;
    const ScenarioMesh& mesh = in.mesh;
    const ScenarioEdit& edit = in.edit;

    std::vector<double> setup, solve, per_iteration;
    SetupParts setup_parts;
    IterationParts solve_parts;
    SessionPtr session;
    Solved solved;
    for (int r = 0; r < repeat; ++r) {
        session.reset();  // one session at a time, so the peak memory is one edit's
        if (ToolStatus s = start_session(mesh, edit, session); !s)
            return ToolStatus(s.code(), path + ": " + s.message());
        if (ToolStatus s = solve_frame(session.get(), solved); !s)
            return ToolStatus(s.code(), path + ": " + s.message());
        setup.push_back(solved.report.setup_ms);
        solve.push_back(solved.info.solve_ms);
        per_iteration.push_back(solved.info.solve_ms / std::max(1u, solved.info.iterations));
        setup_parts.add(solved.details);
        solve_parts.add(solved.details, solved.info.iterations);
    }
    dfm_quality quality = {};
    if (ToolStatus s = api_status(dfm_session_measure_quality(session.get(), &quality, nullptr));
        !s)
        return s;
    session.reset();

    // The drag: a fresh session, targets moved from rest to the scenario's
    // in equal steps, each frame warm-started from the last.
    SessionPtr drag;
    if (ToolStatus s = start_session(mesh, edit, drag); !s) return s;
    std::vector<glm::dvec3> start;
    for (const std::vector<std::uint32_t>& group : edit.groups) {
        for (const std::uint32_t v : group) start.push_back(mesh.rest[v]);
    }
    std::vector<glm::dvec3> frame_targets(start.size());
    std::vector<double> frame_ms;
    std::vector<double> frame_iterations;
    IterationParts frame_parts;
    int unconverged = 0;
    int predicted = 0;
    // The worst frame's folds: a frame a host draws must not fold even
    // where the last one does not. Measured outside the timed solves.
    std::size_t most_flipped = 0;
    std::size_t most_creased = 0;
    for (int f = 1; f <= drag_frames; ++f) {
        const double t = static_cast<double>(f) / drag_frames;
        for (std::size_t h = 0; h < start.size(); ++h)
            frame_targets[h] = start[h] + t * (edit.targets[h] - start[h]);
        if (ToolStatus s = set_targets(drag.get(), frame_targets); !s) return s;
        Solved frame;
        if (ToolStatus s = solve_frame(drag.get(), frame); !s) return s;
        frame_ms.push_back(frame.info.solve_ms);
        frame_iterations.push_back(frame.info.iterations);
        frame_parts.add(frame.details, frame.info.iterations);
        unconverged += frame.info.converged ? 0 : 1;
        predicted += frame.details.predicted ? 1 : 0;
        dfm_quality folds = {};
        if (ToolStatus s = api_status(dfm_session_measure_quality(drag.get(), &folds, nullptr)); !s)
            return s;
        most_flipped = std::max(most_flipped, folds.flipped_faces);
        most_creased = std::max(most_creased, folds.creased_edges);
    }

    // A posed scenario: what posing costs (the skinning, and the posed
    // model an edit builds on first need) and what a bake's corrective
    // costs, the drag's last frame baked and undone.
    PoseTimes pose_times;
    if (scenario.pose) {
        if (ToolStatus s = time_pose(mesh, drag.get(), repeat, pose_times); !s) return s;
    }

    // The drag's session, as it ends, and the mesh: what an edit holds.
    // The peak above them is mostly the library's buffer pool, which keeps
    // a set-up's scratch for the next set-up, and this tool's own arrays.
    dfm_session_memory session_memory = {};
    if (ToolStatus s = api_status(dfm_session_get_memory(drag.get(), &session_memory)); !s)
        return s;
    dfm_mesh_memory mesh_memory = {};
    if (ToolStatus s = api_status(dfm_mesh_get_memory(mesh.mesh.get(), &mesh_memory)); !s) return s;

    const dfm_solve_report& sr = solved.report;
    json.begin_object();
    json.key("scenario").value(path);
    json.key("mesh").value(scenario.mesh);
    json.key("n_vertices").value(std::uint64_t{mesh.info.vertex_count});
    json.key("n_roi").value(std::uint64_t{edit.roi.vertices.size()});
    json.key("n_unknowns").value(std::uint64_t{sr.unknowns});
    json.key("n_rows").value(std::uint64_t{sr.rows});
    json.key("normal_nonzeros").value(std::uint64_t{sr.normal_nonzeros});
    json.key("preconditioner").value(preconditioner_name(edit.solver.preconditioner));
    json.key("repeat").value(std::uint64_t(repeat));
    json.key("workers").value(std::uint64_t{overrides.workers});
    json.key("frame_prediction").value(overrides.predict_frames);
    json.key("tolerance")
        .value(edit.solver.tolerance != 0.0 ? edit.solver.tolerance : default_tolerance);
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
    json.key("iterations").value(std::uint64_t{solved.info.iterations});
    json.key("converged").value(solved.info.converged);
    json.key("krylov_iterations").value(std::uint64_t{sr.krylov_iterations});
    json.key("drag").begin_object();
    json.key("frames").value(std::uint64_t{drag_frames});
    json.key("unconverged_frames").value(std::uint64_t(unconverged));
    json.key("predicted_frames").value(std::uint64_t(predicted));
    json.key("most_flipped_faces").value(std::uint64_t{most_flipped});
    json.key("most_creased_edges").value(std::uint64_t{most_creased});
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
    if (scenario.pose) {
        json.key("pose").begin_object();
        write_spread(json, "set_pose_ms", pose_times.set_pose);
        write_spread(json, "read_positions_ms", pose_times.read);
        write_spread(json, "posed_model_ms", pose_times.posed_model);
        write_spread(json, "bake_corrective_ms", pose_times.bake);
        json.end_object();
    }
    const auto mib = [](std::size_t bytes) { return static_cast<double>(bytes) / (1 << 20); };
    json.key("memory_mib").begin_object();
    json.key("factor").value(mib(session_memory.factor));
    json.key("normal_matrix").value(mib(session_memory.normal_matrix));
    json.key("iteration").value(mib(session_memory.iteration));
    json.key("frame_slots").value(mib(session_memory.frames));
    json.key("staging").value(mib(session_memory.staging));
    json.key("session").value(mib(session_memory.total));
    json.key("mesh_model").value(mib(mesh_memory.total));
    json.end_object();
    json.key("peak_rss_mib").value(peak_rss_mib());
    json.end_object();
    std::fprintf(
        stderr,
        "%-28s setup %8.2f (rows %.2f assembly %.2f ordering %.2f symbolic %.2f "
        "numeric %.2f) | iteration %.3f (solve %.3f rhs %.3f normals %.3f anderson "
        "%.3f) | drag frame %.2f (p99 %.2f), %.0f iterations | session %.1f MiB, mesh %.1f, "
        "peak RSS %.1f\n",
        path.c_str(), median(setup), median(setup_parts.rows), median(setup_parts.assembly),
        median(setup_parts.ordering), median(setup_parts.symbolic), median(setup_parts.numeric),
        median(per_iteration), median(solve_parts.linear), median(solve_parts.rhs),
        median(solve_parts.normals), median(solve_parts.anderson), median(frame_ms),
        percentile(frame_ms, 0.99), median(frame_iterations), mib(session_memory.total),
        mib(mesh_memory.total), peak_rss_mib());
    return ToolStatus::ok();
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
            const std::string_view name = i + 1 < args.size() ? args[++i] : std::string_view{};
            const auto known =
                std::find_if(std::begin(preconditioner_names), std::end(preconditioner_names),
                             [&](const PreconditionerName& n) { return name == n.name; });
            if (known == std::end(preconditioner_names)) {
                return bad_input(
                    "--preconditioner: expected cholesky, incomplete_cholesky or jacobi");
            }
            overrides.preconditioner = known->value;
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
            return bad_input(std::string("unknown option '") + std::string(a) + "'\n" +
                             usage(bench_help));
        } else {
            scenarios.emplace_back(a);
        }
    }
    if (scenarios.empty()) return bad_input(usage(bench_help));
    overrides.workers = static_cast<std::uint32_t>(workers);

    json::JsonWriter json;
    json.begin_object();
    json.key("machine").begin_object();
    json.key("hardware_threads").value(std::uint64_t{std::thread::hardware_concurrency()});
    json.end_object();
    json.key("results").begin_array();
    for (const std::string& path : scenarios) {
        BenchInput input;
        if (ToolStatus s = read_bench_input(path, overrides, input); !s) {
            return bad_input(s.message());
        }
        if (ToolStatus s = bench_scenario(path, input, repeat, overrides, json); !s)
            return work_failure(s);
        std::fprintf(stderr, "bench: %s done\n", path.c_str());
    }
    json.end_array();
    json.end_object();
    std::printf("%s\n", json.str().c_str());
    if (!json_path.empty()) {
        if (ToolStatus s = write_text_file(json_path, json.str()); !s) return work_failure(s);
    }
    return exit_ok;
}

}  // namespace dfm::cli
