// solver_bench: times the sparse solver on systems with the sparsity of a
// real edit (vertex 2-rings of real meshes) and prints JSON.
//
// usage: solver_bench [--models cow,armadillo] [--subdivide S] [--threads T]
//                     [--repeat R] [--tolerance F] [--max-iterations M]
//                     [--krylov-max-vertices V] [--stagnation N]
//   --subdivide S   also each model split into 4^s times the triangles, s ≤ S
//   --tolerance F   PCG stops at max |M⁻¹ r| ≤ F × the bounding-box diagonal
//   --krylov-max-vertices V   Jacobi and IC(0) runs only up to V vertices
//   --stagnation N  PbcgOptions::stagnation_limit (default 0: 3 for the
//                   Cholesky preconditioner, never for the others)

#include <cstdio>
#include <cstdlib>
#include <string>
#include <string_view>
#include <thread>
#include <vector>

#ifdef DFM_SOLVER_BENCH_CHOLMOD
#include "cholmod_peer.hpp"
#endif
#include "environment/host_environment.hpp"
#include "jobs/scheduler.hpp"
#include "json/json_writer.hpp"
#include "measure.hpp"
#include "mesh/load.hpp"
#include "mesh/model_cache.hpp"

namespace {

using namespace dfm;
using namespace dfm::solver_bench;

struct Settings {
    std::vector<std::string> models = {"cow", "armadillo"};
    int subdivide = 1;
    std::size_t threads = std::max(1u, std::thread::hardware_concurrency());
    int repeat = 5;
    double tolerance = 1e-10;
    std::size_t max_iterations = 1000;
    std::size_t krylov_max_vertices = 150000;
    std::size_t stagnation = 0;
};

std::vector<std::string> split(std::string_view list) {
    std::vector<std::string> out;
    while (!list.empty()) {
        const std::size_t comma = list.find(',');
        out.emplace_back(list.substr(0, comma));
        list = comma == std::string_view::npos ? std::string_view{} : list.substr(comma + 1);
    }
    return out;
}

bool parse(int argc, char** argv, Settings& s) {
    for (int i = 1; i < argc; ++i) {
        const std::string_view arg = argv[i];
        if (i + 1 >= argc) return false;
        const char* value = argv[++i];
        if (arg == "--models") {
            s.models = split(value);
        } else if (arg == "--subdivide") {
            s.subdivide = std::atoi(value);
        } else if (arg == "--threads") {
            s.threads = static_cast<std::size_t>(std::max(1, std::atoi(value)));
        } else if (arg == "--repeat") {
            s.repeat = std::max(1, std::atoi(value));
        } else if (arg == "--tolerance") {
            s.tolerance = std::atof(value);
        } else if (arg == "--max-iterations") {
            s.max_iterations = static_cast<std::size_t>(std::atol(value));
        } else if (arg == "--stagnation") {
            s.stagnation = static_cast<std::size_t>(std::atol(value));
        } else if (arg == "--krylov-max-vertices") {
            s.krylov_max_vertices = static_cast<std::size_t>(std::atol(value));
        } else {
            return false;
        }
    }
    return true;
}

void write_factor(json::JsonWriter& json, const FactorMeasure& f) {
    json.begin_object()
        .field("ordering", solver::ordering_method_name(f.ordering))
        .field("graph_ms", f.graph_ms)
        .field("ordering_ms", f.ordering_ms)
        .field("symbolic_ms", f.symbolic_ms)
        .field("numeric_ms", f.numeric_ms)
        .field("setup_ms", f.setup_ms)
        .field("setup_min_ms", f.setup_min_ms)
        .field("solve_k3_ms", f.solve_k3_ms)
        .field("solve_k3_min_ms", f.solve_k3_min_ms)
        .field("factor_nonzeros", f.factor_nonzeros)
        .field("stored_values", f.stored_values)
        .field("supernodes", f.supernodes)
        .field("flops", f.flops)
        .field("solve_relative_residual", f.solve_relative_residual)
        .end_object();
}

void write_solve(json::JsonWriter& json, const SolveMeasure& s) {
    json.begin_object()
        .field("preconditioner", s.preconditioner.c_str())
        .field("start", s.warm ? "warm" : "cold")
        .field("setup_ms", s.setup_ms)
        .field("solve_ms", s.solve_ms)
        .field("solve_min_ms", s.solve_min_ms)
        .field("iterations", s.iterations)
        .field("converged", s.converged)
        .field("stagnated", s.stagnated)
        .field("error_estimate_over_diagonal", s.error_estimate)
        .field("true_error_over_diagonal", s.true_error)
        .field("relative_residual", s.relative_residual)
        .end_object();
}

}  // namespace

int main(int argc, char** argv) {
    Settings settings;
    if (!parse(argc, argv, settings)) {
        std::fprintf(stderr,
                     "usage: solver_bench [--models cow,armadillo] [--subdivide S] [--threads T] "
                     "[--repeat R] [--tolerance F] [--max-iterations M] "
                     "[--krylov-max-vertices V] [--stagnation N]\n");
        return 2;
    }
    jobs::Scheduler pool(jobs::SchedulerConfig::threads(settings.threads));
    json::JsonWriter json(json::JsonWriter::Layout::indented);
    json.begin_object()
        .field("threads", settings.threads)
        .field("hardware_threads", static_cast<std::size_t>(std::thread::hardware_concurrency()))
        .field("tolerance_over_diagonal", settings.tolerance)
        .key("systems")
        .begin_array();
    for (const std::string& model : settings.models) {
        std::filesystem::path path;
        mesh::Mesh base;
        if (Status st = mesh::resolve_mesh_spec("model:" + model, ".",
                                                tools::models_folder_from_environment(), path);
            !st) {
            std::fprintf(stderr, "solver_bench: %s\n", st.message().c_str());
            return 1;
        }
        if (Status st = mesh::load_mesh(path, base); !st) {
            std::fprintf(stderr, "solver_bench: %s\n", st.message().c_str());
            return 1;
        }
        mesh::Mesh mesh = base;
        for (int level = 0; level <= settings.subdivide; ++level) {
            if (level > 0) mesh = subdivide_midpoint(mesh);
            const TestSystem system = make_test_system(mesh);
            const std::size_t n = system.matrix.rows;
            const int repeat = n > 200000 ? 1 : settings.repeat;
            std::fprintf(stderr, "solver_bench: %s x%d, %zu unknowns\n", model.c_str(), level, n);
            json.begin_object()
                .field("model", model.c_str())
                .field("subdivisions", static_cast<std::size_t>(level))
                .field("unknowns", n)
                .field("nonzeros", system.matrix.nonzeros())
                .key("factor");
            write_factor(
                json, measure_factor(system, solver::OrderingMethod::minimum_degree, pool, repeat));
#ifdef DFM_SOLVER_BENCH_CHOLMOD
            const CholmodMeasure cholmod = measure_cholmod(system, repeat);
            if (cholmod.ok) {
                json.key("cholmod")
                    .begin_object()
                    .field("ordering", "minimum degree (ours, given)")
                    .field("symbolic_ms", cholmod.symbolic_ms)
                    .field("numeric_ms", cholmod.numeric_ms)
                    .field("solve_k3_ms", cholmod.solve_k3_ms)
                    .field("solve_k3_min_ms", cholmod.solve_k3_min_ms)
                    .field("factor_nonzeros", cholmod.factor_nonzeros)
                    .field("solve_relative_residual", cholmod.solve_relative_residual)
                    .end_object();
            }
#endif
            json.key("pcg").begin_array();
            const Frame frame = make_frame(system, mesh, pool);
            const double tolerance = settings.tolerance * system.diagonal;
            for (const solver::PreconditionerKind kind :
                 {solver::PreconditionerKind::cholesky,
                  solver::PreconditionerKind::incomplete_cholesky,
                  solver::PreconditionerKind::jacobi}) {
                if (kind != solver::PreconditionerKind::cholesky &&
                    n > settings.krylov_max_vertices)
                    continue;
                solver::PbcgOptions options;
                options.tolerance = tolerance;
                options.max_iterations = settings.max_iterations;
                options.stagnation_limit = settings.stagnation;
                options.pool = &pool;
                // The iterative runs are long: timed once.
                const int runs = kind == solver::PreconditionerKind::cholesky ? repeat : 1;
                for (const bool warm : {true, false})
                    write_solve(json, measure_pcg(system, frame, kind, warm, options, runs));
            }
            json.end_array().end_object();
        }
    }
    json.end_array().end_object();
    std::printf("%s\n", json.str().c_str());
    return 0;
}
