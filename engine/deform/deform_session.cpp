#include "deform/deform_session.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <limits>
#include <new>
#include <string>

#include <glm/geometric.hpp>

#include "core/memory_bytes.hpp"
#include "core/stopwatch.hpp"
#include "deform/fitted_iteration.hpp"
#include "deform/paper_iteration.hpp"
#include "deform/row_order.hpp"
#include "solver/parallel_kernels.hpp"

namespace dfm::deform {

namespace {

// Accuracy of each linear solve, in units of the rest diagonal.
constexpr double linear_tolerance = 1e-8;

// Steps of history for Anderson acceleration of the outer iteration.
constexpr std::size_t anderson_memory = 8;

constexpr double infinity = std::numeric_limits<double>::infinity();

}  // namespace

const char* method_name(DeformMethod m) {
    return m == DeformMethod::paper ? "paper" : "fitted_rotations";
}

void IterationState::store(std::span<const double> iterate) {
    jobs::for_parts(settings->pool, unknowns->count(), [&](std::size_t begin, std::size_t end) {
        for (std::size_t i = begin; i < end; ++i) {
            positions[unknowns->vertex_of_unknown[i]] = {iterate[3 * i], iterate[3 * i + 1],
                                                         iterate[3 * i + 2]};
        }
    });
}

DeformSession::DeformSession(const MeshModel& model, const DeformSettings& settings)
    : model_(model), settings_(settings) {
    state_.model = &model_;
    state_.settings = &settings_;
    state_.unknowns = &unknowns_;
}

Status DeformSession::create(const MeshModel& model, std::span<const std::uint32_t> roi,
                             std::span<const std::vector<std::uint32_t>> handle_groups,
                             const DeformSettings& settings, std::unique_ptr<DeformSession>& out,
                             const std::atomic<bool>* stop) {
    out.reset();
    const auto start = std::chrono::steady_clock::now();
    if (!(settings.tolerance > 0.0) || settings.max_iterations < 1 ||
        !(settings.handle_weight > 0.0) ||
        (settings.method != DeformMethod::fitted_rotations &&
         settings.method != DeformMethod::paper)) {
        return Status(Errc::invalid_argument,
                      "solver settings: tolerance and handle weight must be positive, the "
                      "iteration cap at least 1, the method one of fitted_rotations and paper");
    }
    try {
        std::unique_ptr<DeformSession> s(new DeformSession(model, settings));
        if (Status st = s->select_unknowns(roi, handle_groups); !st) return st;
        if (Status st = s->build_system(stop); !st) return st;
        s->start_iteration();
        s->setup_.setup_ms = ms_since(start);
        out = std::move(s);
        return Status::ok();
    } catch (const std::bad_alloc&) {
        return Status(Errc::out_of_memory, "out of memory while setting up the edit");
    }
}

// The unknowns are the ROI's vertices but those next to the outside, which
// stitch the edit to the rest of the mesh and stay put; a handle there
// follows its target instead, as in the CGAL peer's set-up. Hard handles
// are no unknowns either.
Status DeformSession::select_unknowns(std::span<const std::uint32_t> roi,
                                      std::span<const std::vector<std::uint32_t>> handle_groups) {
    const std::size_t n = model_.mesh.vertex_count();
    std::vector<std::uint8_t> in_roi(n, 0);
    for (std::uint32_t v : roi) {
        if (v >= n) {
            return Status(Errc::out_of_range, "ROI vertex " + std::to_string(v) +
                                                  " is out of range (the mesh has " +
                                                  std::to_string(n) + " vertices)");
        }
        in_roi[v] = 1;
    }
    std::vector<std::uint8_t> is_handle(n, 0);
    for (std::size_t g = 0; g < handle_groups.size(); ++g) {
        for (std::uint32_t v : handle_groups[g]) {
            const std::string where =
                "handle group " + std::to_string(g) + ": vertex " + std::to_string(v);
            if (v >= n) {
                return Status(Errc::out_of_range, where + " is out of range (the mesh has " +
                                                      std::to_string(n) + " vertices)");
            }
            if (!in_roi[v]) return Status(Errc::invalid_argument, where + " is outside the ROI");
            if (is_handle[v]) {
                return Status(Errc::invalid_argument, where + " is in an earlier group too");
            }
            is_handle[v] = 1;
            state_.handle_vertices.push_back(v);
        }
    }
    std::vector<std::uint8_t> movable(in_roi);
    bool has_boundary = false;
    for (std::uint32_t v = 0; v < n; ++v) {
        if (!in_roi[v]) continue;
        for (std::uint32_t w : model_.vertex_neighbors.of(v)) {
            if (!in_roi[w]) {
                has_boundary = true;
                if (!is_handle[v]) movable[v] = 0;
                break;
            }
        }
    }
    if (state_.handle_vertices.empty() && !has_boundary) {
        return Status(Errc::invalid_argument,
                      "nothing pins the ROI: it has no boundary, so it needs a handle group");
    }
    state_.pinned = has_boundary;
    if (settings_.hard_handles) {
        for (std::uint32_t v : state_.handle_vertices) movable[v] = 0;
    }
    unknowns_.unknown_of_vertex.assign(n, mesh::no_index);
    for (std::uint32_t v = 0; v < n; ++v) {
        if (!movable[v]) continue;
        unknowns_.unknown_of_vertex[v] = static_cast<std::uint32_t>(unknowns_.count());
        unknowns_.vertex_of_unknown.push_back(v);
    }
    if (!settings_.hard_handles) {
        for (std::uint32_t v : state_.handle_vertices)
            state_.soft_handles.push_back(unknowns_.unknown_of_vertex[v]);
    }
    return Status::ok();
}

// The rows, the method's own rows and N, and N's factor. `stop` (optional)
// is looked at between the phases and inside the factorization.
Status DeformSession::build_system(const std::atomic<bool>* stop) {
    const auto stopped = [stop] {
        return stop != nullptr && stop->load(std::memory_order_relaxed);
    };
    const Status cancelled(Errc::cancelled, "the set-up of the edit was stopped");
    const auto phase = std::chrono::steady_clock::now();
    SystemRows rows = collect_rows(model_, unknowns_);
    // The fitted method's rows and unknowns are put in the surface's order
    // (row_order.hpp) after its clusters are made: the clusters depend on
    // the rows' numbering (each patch grows from the lowest row left), and
    // made over the rows as collect_rows lists them they stay the same.
    RotationClusters clusters;
    if (settings_.method == DeformMethod::fitted_rotations) {
        clusters = coarse_clusters(model_, rows);
        order_by_patch(clusters, rows, unknowns_, state_.soft_handles);
    }
    if (stopped()) return cancelled;
    solver::CsrMatrix normal;
    const auto build_and_assemble = [&] {
        if (settings_.method == DeformMethod::fitted_rotations) {
            auto fitted = std::make_unique<FittedIteration>(model_, unknowns_, rows, clusters);
            setup_.rows_ms = ms_since(phase);
            const auto assembly = std::chrono::steady_clock::now();
            normal = fitted->assemble_normal_matrix(state_, stop);
            setup_.assembly_ms = ms_since(assembly);
            method_ = std::move(fitted);
        } else {
            setup_.rows_ms = ms_since(phase);
            const auto assembly = std::chrono::steady_clock::now();
            normal = deform::assemble_normal_matrix(rows, unknowns_.count(), state_.soft_handles,
                                                    settings_.handle_weight,
                                                    relative_regularization, state_.epsilon, stop);
            setup_.assembly_ms = ms_since(assembly);
        }
    };
    // The complete factor's ordering and symbolic analysis need only N's
    // pattern, which the dual rows give: with a second worker they run
    // beside the rigidity rows and the assembly. The same results either
    // way, in less time.
    if (settings_.pool != nullptr && settings_.pool->thread_count() > 1 &&
        settings_.preconditioner == solver::PreconditionerKind::cholesky &&
        unknowns_.count() >= jobs::parallel_minimum) {
        Status analyzed = Status::ok();
        std::array<bool, 2> out_of_memory{};
        settings_.pool->run(2, [&](std::size_t task) {
            try {
                if (task == 0) {
                    build_and_assemble();
                } else {
                    analyzed = linear_.analyze(normal_pattern(rows, unknowns_.count()),
                                               settings_.preconditioner, settings_.pool, stop);
                }
            } catch (const std::bad_alloc&) {
                out_of_memory[task] = true;
            }
        });
        if (out_of_memory[0] || out_of_memory[1]) throw std::bad_alloc();
        if (stopped()) return cancelled;
        if (!analyzed) return analyzed;
    } else {
        build_and_assemble();
    }
    // The fitted rotations read their stencils alone: the rows go before
    // the factor needs room. The paper's method keeps them.
    if (settings_.method == DeformMethod::paper) {
        method_ = std::make_unique<PaperIteration>(model_, std::move(rows));
    } else {
        SystemRows released;
        std::swap(rows, released);
    }
    setup_.normal_nonzeros = normal.nonzeros();
    if (stopped()) return cancelled;
    if (Status st =
            linear_.setup(std::move(normal), settings_.preconditioner, settings_.pool, stop);
        !st) {
        return st;
    }
    const solver::CholeskyTimes factor_times = linear_.factor_times();
    setup_.ordering_ms = factor_times.ordering_ms;
    setup_.symbolic_ms = factor_times.symbolic_ms;
    setup_.numeric_ms = factor_times.numeric_ms;
    setup_.unknowns = unknowns_.count();
    setup_.rows = method_->rows();
    return Status::ok();
}

// The iteration's vectors, at the rest pose: the converged frame of the
// rest targets.
void DeformSession::start_iteration() {
    const std::size_t size = 3 * unknowns_.count();
    state_.positions.assign(model_.mesh.positions.begin(), model_.mesh.positions.end());
    state_.targets.resize(state_.handle_vertices.size());
    for (std::size_t h = 0; h < state_.handle_vertices.size(); ++h) {
        state_.targets[h] = state_.positions[state_.handle_vertices[h]];
    }
    state_.rhs.resize(size);
    state_.x.resize(size);
    state_.current.resize(size);
    state_.next.resize(size);
    state_.anderson.reset(size, anderson_memory);
    predictor_.reset(size, state_.handle_vertices.size());
    for (std::size_t i = 0; i < unknowns_.count(); ++i) {
        const glm::dvec3& p = state_.positions[unknowns_.vertex_of_unknown[i]];
        for (int c = 0; c < 3; ++c) state_.current[3 * i + c] = p[c];
    }
    predictor_.record(state_.current, state_.targets);
}

SessionMemory DeformSession::memory() const {
    const LinearSolver::Memory linear = linear_.memory();
    SessionMemory m;
    m.factor = linear.preconditioner;
    m.system = linear.matrix + method_->memory_bytes() +
               capacity_bytes(unknowns_.unknown_of_vertex, unknowns_.vertex_of_unknown,
                              state_.handle_vertices, state_.soft_handles);
    m.iteration = linear.workspace + state_.anderson.memory_bytes() + predictor_.memory_bytes() +
                  capacity_bytes(state_.targets, state_.positions, state_.rhs, state_.x,
                                 state_.current, state_.next);
    return m;
}

Status DeformSession::set_targets(std::span<const glm::dvec3> targets) {
    const std::span<const std::uint32_t> handles = state_.handle_vertices;
    if (targets.size() != handles.size()) {
        return Status(Errc::invalid_argument, "expected " + std::to_string(handles.size()) +
                                                  " targets, got " +
                                                  std::to_string(targets.size()));
    }
    for (std::size_t h = 0; h < targets.size(); ++h) {
        const glm::dvec3& t = targets[h];
        if (!std::isfinite(t.x) || !std::isfinite(t.y) || !std::isfinite(t.z)) {
            return Status(Errc::invalid_argument, "target " + std::to_string(h) + " (vertex " +
                                                      std::to_string(handles[h]) +
                                                      ") is not finite");
        }
    }
    std::copy(targets.begin(), targets.end(), state_.targets.begin());
    if (settings_.hard_handles) {
        for (std::size_t h = 0; h < handles.size(); ++h)
            state_.positions[handles[h]] = state_.targets[h];
    }
    return Status::ok();
}

Status DeformSession::set_positions(std::span<const glm::dvec3> positions) {
    if (positions.size() != state_.positions.size()) {
        return Status(Errc::invalid_argument,
                      "expected " + std::to_string(state_.positions.size()) + " positions, got " +
                          std::to_string(positions.size()));
    }
    for (std::uint32_t v : unknowns_.vertex_of_unknown) {
        const glm::dvec3& p = positions[v];
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) {
            return Status(Errc::invalid_argument,
                          "position of vertex " + std::to_string(v) + " is not finite");
        }
    }
    for (std::uint32_t v : unknowns_.vertex_of_unknown) state_.positions[v] = positions[v];
    predictor_.forget();
    return Status::ok();
}

Status DeformSession::set_stopping_rule(double tolerance, int max_iterations) {
    if (!(tolerance > 0.0) || !std::isfinite(tolerance) || max_iterations < 1) {
        return Status(Errc::invalid_argument,
                      "the tolerance must be positive and finite, the iteration cap at least 1");
    }
    settings_.tolerance = tolerance;
    settings_.max_iterations = max_iterations;
    return Status::ok();
}

// The plain step's length |G(x) - x|, the convergence measure: the largest
// vertex move from current to x, a NaN counting as infinite, so that a
// non-finite solution shows as an infinite length; the positions keep the
// last good state. A maximum: the same on any number of workers.
double DeformSession::plain_step_length() const {
    const std::span<const double> x = state_.x;
    const std::span<const double> current = state_.current;
    std::atomic<double> largest{0.0};
    jobs::for_parts(settings_.pool, unknowns_.count(), [&](std::size_t begin, std::size_t end) {
        double part = 0.0;
        for (std::size_t i = begin; i < end && part != infinity; ++i) {
            const glm::dvec3 step(x[3 * i] - current[3 * i], x[3 * i + 1] - current[3 * i + 1],
                                  x[3 * i + 2] - current[3 * i + 2]);
            const double move = glm::length(step);
            part = std::isnan(move) ? infinity : std::max(part, move);
        }
        double seen = largest.load(std::memory_order_relaxed);
        while (part > seen &&
               !largest.compare_exchange_weak(seen, part, std::memory_order_relaxed)) {
        }
    });
    return largest.load(std::memory_order_relaxed);
}

Status DeformSession::solve(SolveReport& report, const Control* control) {
    paused_.active = false;
    report = SolveReport{};
    const auto start = std::chrono::steady_clock::now();
    // A prediction writes every unknown's start; without one the frame
    // starts where the last ended.
    report.predicted = settings_.predict_frames &&
                       predictor_.predict(state_.targets, state_.current, settings_.pool);
    if (!report.predicted) {
        for (std::size_t i = 0; i < unknowns_.count(); ++i) {
            const glm::dvec3& p = state_.positions[unknowns_.vertex_of_unknown[i]];
            for (int c = 0; c < 3; ++c) state_.current[3 * i + c] = p[c];
        }
    }
    const double carried = method_->start(state_, report);
    return iterate(report, control, 0, carried, start);
}

Status DeformSession::resume(SolveReport& report, const Control* control) {
    if (!paused_.active) return Status(Errc::invalid_argument, "no solve is paused");
    paused_.active = false;
    report = paused_.report;
    report.paused = false;
    const auto start = std::chrono::steady_clock::now() -
                       std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                           std::chrono::duration<double, std::milli>(paused_.elapsed_ms));
    return iterate(report, control, paused_.iteration, paused_.carried, start);
}

bool DeformSession::pause_before(int it, int first, double carried,
                                 std::chrono::steady_clock::time_point start,
                                 const Control* control, SolveReport& report) {
    if (it == first || control == nullptr ||
        std::chrono::steady_clock::now() < control->pause_after) {
        return false;
    }
    report.solve_ms = ms_since(start);
    report.paused = true;
    paused_ = Paused{true, it, carried, report.solve_ms, report};
    return true;
}

Status DeformSession::iterate(SolveReport& report, const Control* control, int first,
                              double carried, std::chrono::steady_clock::time_point start) {
    const std::atomic<bool>* interrupt = control != nullptr ? control->interrupt : nullptr;
    const double diag = model_.diagonal > 0.0 ? model_.diagonal : 1.0;
    for (int it = first; it < settings_.max_iterations; ++it) {
        if (it > 0 && interrupt != nullptr && interrupt->load(std::memory_order_acquire)) {
            report.interrupted = true;
            report.solve_ms = ms_since(start);
            return Status::ok();
        }
        if (pause_before(it, first, carried, start, control, report)) return Status::ok();
        std::size_t krylov = 0;
        const auto phase = std::chrono::steady_clock::now();
        if (Status s = linear_.solve(state_.rhs, state_.x, linear_tolerance * diag,
                                     LinearSolver::Accuracy::one_step, krylov);
            !s) {
            report.solve_ms = ms_since(start);
            return s;
        }
        report.linear_ms += ms_since(phase);
        report.krylov_iterations += krylov;
        report.iterations = it + 1;
        report.last_update = plain_step_length() / diag;
        if (!std::isfinite(report.last_update)) {
            report.solve_ms = ms_since(start);
            return Status(Errc::numerical,
                          "the solve produced non-finite positions; the last "
                          "finite result is kept");
        }
        if (report.last_update < settings_.tolerance) {
            report.converged = true;
            break;
        }
        if (it + 1 == settings_.max_iterations) break;
        carried = method_->advance(state_, report, carried);
        if (control != nullptr && control->on_iteration) control->on_iteration(report);
    }
    verify_last_solve(report);
    report.solve_ms = ms_since(start);
    return Status::ok();
}

void DeformSession::verify_last_solve(SolveReport& report) {
    const double diag = model_.diagonal > 0.0 ? model_.diagonal : 1.0;
    // The last linear solve, confirmed to its tolerance: what the host gets
    // is the solution of the last system, not one unchecked step of it. On a
    // nearly singular system the confirmation can fail; then the unchecked
    // step, which is finite, stands.
    solver::kernels::copy(state_.x, state_.next, settings_.pool);
    std::size_t krylov = 0;
    const auto verify_start = std::chrono::steady_clock::now();
    const Status verified = linear_.solve(state_.rhs, state_.x, linear_tolerance * diag,
                                          LinearSolver::Accuracy::verified, krylov);
    report.linear_ms += ms_since(verify_start);
    report.krylov_iterations += krylov;
    report.linear_converged = verified.is_ok() && linear_.converged();
    if (report.linear_converged) {
        report.linear_residual = linear_.relative_residual();
    } else {
        report.linear_residual = std::numeric_limits<double>::quiet_NaN();
        solver::kernels::copy(state_.next, state_.x, settings_.pool);
    }
    state_.store(state_.x);
    if (report.converged) predictor_.record(state_.x, state_.targets, settings_.pool);
}

}  // namespace dfm::deform
