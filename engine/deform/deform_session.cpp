#include "deform/deform_session.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <new>
#include <string>

#include <glm/geometric.hpp>

#include "core/memory_bytes.hpp"
#include "core/stopwatch.hpp"

namespace dfm::deform {

const char* method_name(DeformMethod m) {
    return m == DeformMethod::paper ? "paper" : "fitted_rotations";
}

Status DeformSession::create(const MeshModel& model, std::span<const std::uint32_t> roi,
                             std::span<const std::vector<std::uint32_t>> handle_groups,
                             const DeformSettings& settings, std::unique_ptr<DeformSession>& out,
                             const std::atomic<bool>* stop) {
    out.reset();
    const auto stopped = [stop] {
        return stop != nullptr && stop->load(std::memory_order_relaxed);
    };
    const Status cancelled(Errc::cancelled, "the set-up of the edit was stopped");
    const auto start = std::chrono::steady_clock::now();
    const std::size_t n = model.mesh.vertex_count();
    if (!(settings.tolerance > 0.0) || settings.max_iterations < 1 ||
        !(settings.handle_weight > 0.0) || !(settings.regularization >= 0.0) ||
        !(settings.linear_tolerance > 0.0) || settings.anderson_memory < 0 ||
        settings.anderson_memory > 50 || !(settings.rigidity_weight >= 0.0) ||
        !std::isfinite(settings.rigidity_weight) ||
        (settings.method != DeformMethod::fitted_rotations &&
         settings.method != DeformMethod::paper)) {
        return Status(Errc::invalid_argument,
                      "solver settings: tolerance, handle weight and linear tolerance must be "
                      "positive, the iteration cap at least 1, the regularization not negative, "
                      "the Anderson memory from 0 to 50, the rigidity weight finite and not "
                      "negative, the method one of fitted_rotations and paper");
    }
    try {
        std::unique_ptr<DeformSession> s(new DeformSession(model));
        s->settings_ = settings;
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
                if (!in_roi[v])
                    return Status(Errc::invalid_argument, where + " is outside the ROI");
                if (is_handle[v]) {
                    return Status(Errc::invalid_argument, where + " is in an earlier group too");
                }
                is_handle[v] = 1;
                s->handle_vertices_.push_back(v);
            }
        }
        // ROI vertices next to the outside stay put: they stitch the edit to
        // the rest of the mesh. A handle there follows its target instead,
        // as in the CGAL peer's set-up.
        std::vector<std::uint8_t> movable(in_roi);
        bool has_boundary = false;
        for (std::uint32_t v = 0; v < n; ++v) {
            if (!in_roi[v]) continue;
            for (std::uint32_t w : model.vertex_neighbors.of(v)) {
                if (!in_roi[w]) {
                    has_boundary = true;
                    if (!is_handle[v]) movable[v] = 0;
                    break;
                }
            }
        }
        if (s->handle_vertices_.empty() && !has_boundary) {
            return Status(Errc::invalid_argument,
                          "nothing pins the ROI: it has no boundary, so it needs a handle group");
        }
        s->pinned_ = has_boundary;
        if (settings.hard_handles) {
            for (std::uint32_t v : s->handle_vertices_) movable[v] = 0;
        }

        UnknownMap& u = s->unknowns_;
        u.unknown_of_vertex.assign(n, mesh::no_index);
        for (std::uint32_t v = 0; v < n; ++v) {
            if (!movable[v]) continue;
            u.unknown_of_vertex[v] = static_cast<std::uint32_t>(u.vertex_of_unknown.size());
            u.vertex_of_unknown.push_back(v);
        }
        if (!settings.hard_handles) {
            for (std::uint32_t v : s->handle_vertices_) {
                s->soft_handles_.push_back(u.unknown_of_vertex[v]);
            }
        }
        const auto phase = std::chrono::steady_clock::now();
        s->rows_ = collect_rows(model, u);
        if (stopped()) return cancelled;
        solver::CsrMatrix normal;
        const auto build_and_assemble = [&] {
            if (settings.method == DeformMethod::fitted_rotations) {
                s->frames_.build(model, u, settings.rigidity_weight, s->rows_);
            }
            s->setup_.rows_ms = ms_since(phase);
            const auto assembly = std::chrono::steady_clock::now();
            normal = settings.method == DeformMethod::fitted_rotations
                         ? s->frames_.assemble_normal_matrix(
                               u.count(), s->soft_handles_, settings.handle_weight,
                               settings.regularization, s->epsilon_, stop)
                         : assemble_normal_matrix(s->rows_, u.count(), s->soft_handles_,
                                                  settings.handle_weight, settings.regularization,
                                                  s->epsilon_, stop);
            s->setup_.assembly_ms = ms_since(assembly);
        };
        // The complete factor's ordering and symbolic analysis need only N's
        // pattern, which the dual rows give: with a second worker they run
        // beside the rigidity rows and the assembly. The same results
        // either way, in less time.
        if (settings.pool != nullptr && settings.pool->thread_count() > 1 &&
            settings.preconditioner == solver::PreconditionerKind::cholesky &&
            u.count() >= jobs::parallel_minimum) {
            Status analyzed = Status::ok();
            std::array<bool, 2> out_of_memory{};
            settings.pool->run(2, [&](std::size_t task) {
                try {
                    if (task == 0) {
                        build_and_assemble();
                    } else {
                        analyzed = s->linear_.analyze(normal_pattern(s->rows_, u.count()),
                                                      settings.preconditioner, settings.pool, stop);
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
        const std::size_t normal_nonzeros = normal.nonzeros();
        if (stopped()) return cancelled;
        // From here on the fitted rotations read the rows' faces alone, the
        // rest being in the stencils: the entries go before the factor
        // needs room.
        if (settings.method == DeformMethod::fitted_rotations) s->rows_.release_entries();
        if (Status st =
                s->linear_.setup(std::move(normal), settings.preconditioner, settings.pool, stop);
            !st) {
            return st;
        }
        const solver::CholeskyTimes factor_times = s->linear_.factor_times();
        s->setup_.ordering_ms = factor_times.ordering_ms;
        s->setup_.symbolic_ms = factor_times.symbolic_ms;
        s->setup_.numeric_ms = factor_times.numeric_ms;

        s->positions_.assign(model.mesh.positions.begin(), model.mesh.positions.end());
        s->targets_.resize(s->handle_vertices_.size());
        for (std::size_t h = 0; h < s->handle_vertices_.size(); ++h) {
            s->targets_[h] = s->positions_[s->handle_vertices_[h]];
        }
        if (settings.method == DeformMethod::paper) {
            s->centroids_.assign(model.mesh.face_count(), glm::dvec3(0.0));
            s->dual_targets_.resize(s->rows_.size());
        }
        s->rhs_.resize(3 * u.count());
        s->x_.resize(3 * u.count());
        s->current_.resize(3 * u.count());
        s->next_.resize(3 * u.count());
        s->anderson_.reset(3 * u.count(), static_cast<std::size_t>(settings.anderson_memory));
        s->predictor_.reset(3 * u.count(), s->handle_vertices_.size());
        // The rest pose is the converged frame of the rest targets.
        for (std::size_t i = 0; i < u.count(); ++i) {
            const glm::dvec3& p = s->positions_[u.vertex_of_unknown[i]];
            for (int c = 0; c < 3; ++c) s->current_[3 * i + c] = p[c];
        }
        s->predictor_.record(s->current_, s->targets_);
        s->setup_.unknowns = u.count();
        s->setup_.rows = s->rows_.size() + s->frames_.rigidity_rows();
        s->setup_.normal_nonzeros = normal_nonzeros;
        s->setup_.setup_ms = ms_since(start);
        out = std::move(s);
        return Status::ok();
    } catch (const std::bad_alloc&) {
        return Status(Errc::out_of_memory, "out of memory while setting up the edit");
    }
}

SessionMemory DeformSession::memory() const {
    const LinearSolver::Memory linear = linear_.memory();
    SessionMemory m;
    m.factor = linear.preconditioner;
    m.system = linear.matrix + rows_.memory_bytes() + frames_.memory_bytes() +
               capacity_bytes(unknowns_.unknown_of_vertex, unknowns_.vertex_of_unknown,
                              handle_vertices_, soft_handles_);
    m.iteration =
        linear.workspace + anderson_.memory_bytes() + predictor_.memory_bytes() +
        capacity_bytes(targets_, positions_, centroids_, dual_targets_, rhs_, x_, current_, next_);
    return m;
}

Status DeformSession::set_targets(std::span<const glm::dvec3> targets) {
    if (targets.size() != handle_vertices_.size()) {
        return Status(Errc::invalid_argument,
                      "expected " + std::to_string(handle_vertices_.size()) + " targets, got " +
                          std::to_string(targets.size()));
    }
    for (std::size_t h = 0; h < targets.size(); ++h) {
        const glm::dvec3& t = targets[h];
        if (!std::isfinite(t.x) || !std::isfinite(t.y) || !std::isfinite(t.z)) {
            return Status(Errc::invalid_argument, "target " + std::to_string(h) + " (vertex " +
                                                      std::to_string(handle_vertices_[h]) +
                                                      ") is not finite");
        }
    }
    std::copy(targets.begin(), targets.end(), targets_.begin());
    if (settings_.hard_handles) {
        for (std::size_t h = 0; h < targets_.size(); ++h) {
            positions_[handle_vertices_[h]] = targets_[h];
        }
    }
    return Status::ok();
}

Status DeformSession::set_positions(std::span<const glm::dvec3> positions) {
    if (positions.size() != positions_.size()) {
        return Status(Errc::invalid_argument, "expected " + std::to_string(positions_.size()) +
                                                  " positions, got " +
                                                  std::to_string(positions.size()));
    }
    for (std::uint32_t v : unknowns_.vertex_of_unknown) {
        const glm::dvec3& p = positions[v];
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) {
            return Status(Errc::invalid_argument,
                          "position of vertex " + std::to_string(v) + " is not finite");
        }
    }
    for (std::uint32_t v : unknowns_.vertex_of_unknown) positions_[v] = positions[v];
    predictor_.forget();
    return Status::ok();
}

// Step 2 of the iteration: l_r = -h n, with the rest height and the normal
// of the current 1-ring.
void DeformSession::compute_dual_targets() {
    const mesh::Mesh& mesh = model_.mesh;
    for (std::uint32_t f : rows_.centroid_faces) {
        const mesh::Triangle& t = mesh.triangles[f];
        centroids_[f] = (positions_[t[0]] + positions_[t[1]] + positions_[t[2]]) / 3.0;
    }
    for (std::size_t r = 0; r < rows_.size(); ++r) {
        const std::uint32_t f = rows_.faces[r];
        dual_targets_[r] = -model_.dual.heights[f] * dual::ring_normal(model_.dual, centroids_, f);
    }
}

// rhs = Aᵀ (l - A_fixed p_fixed) + w² u + ε x_previous.
void DeformSession::compute_right_hand_side() {
    std::fill(rhs_.begin(), rhs_.end(), 0.0);
    for (std::size_t r = 0; r < rows_.size(); ++r) {
        glm::dvec3 b = dual_targets_[r];
        for (std::uint32_t p = rows_.entry_offsets[r]; p < rows_.entry_offsets[r + 1]; ++p) {
            const RowEntry& e = rows_.entries[p];
            if (e.unknown == mesh::no_index) b -= e.coefficient * positions_[e.vertex];
        }
        for (std::uint32_t p = rows_.entry_offsets[r]; p < rows_.entry_offsets[r + 1]; ++p) {
            const RowEntry& e = rows_.entries[p];
            if (e.unknown == mesh::no_index) continue;
            for (int c = 0; c < 3; ++c) rhs_[3 * e.unknown + c] += e.coefficient * b[c];
        }
    }
    const double w2 = settings_.handle_weight * settings_.handle_weight;
    for (std::size_t h = 0; h < soft_handles_.size(); ++h) {
        for (int c = 0; c < 3; ++c) rhs_[3 * soft_handles_[h] + c] += w2 * targets_[h][c];
    }
    for (std::size_t i = 0; i < unknowns_.count(); ++i) {
        const glm::dvec3& p = positions_[unknowns_.vertex_of_unknown[i]];
        for (int c = 0; c < 3; ++c) rhs_[3 * i + c] += epsilon_ * p[c];
    }
}

void DeformSession::store_solution() {
    for (std::size_t i = 0; i < unknowns_.count(); ++i) {
        positions_[unknowns_.vertex_of_unknown[i]] = {x_[3 * i], x_[3 * i + 1], x_[3 * i + 2]};
    }
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
// vertex move from current_ to x_. NaN fails every comparison, so a
// non-finite solution shows as a non-finite length; the positions keep the
// last good state.
double DeformSession::plain_step_length() const {
    double largest = 0.0;
    for (std::size_t i = 0; i < unknowns_.count(); ++i) {
        const glm::dvec3 step(x_[3 * i] - current_[3 * i], x_[3 * i + 1] - current_[3 * i + 1],
                              x_[3 * i + 2] - current_[3 * i + 2]);
        const double move = glm::length(step);
        largest = std::isfinite(move) ? std::max(largest, move) : move;
        if (!std::isfinite(largest)) break;
    }
    return largest;
}

Status DeformSession::solve(SolveReport& report, const Control* control) {
    paused_.active = false;
    report = SolveReport{};
    const auto start = std::chrono::steady_clock::now();
    for (std::size_t i = 0; i < unknowns_.count(); ++i) {
        const glm::dvec3& p = positions_[unknowns_.vertex_of_unknown[i]];
        for (int c = 0; c < 3; ++c) current_[3 * i + c] = p[c];
    }
    report.predicted = settings_.predict_frames && predictor_.predict(targets_, current_);
    if (settings_.method == DeformMethod::fitted_rotations) return solve_fitted(report, control);
    std::copy(current_.begin(), current_.end(), x_.begin());
    if (report.predicted) store_solution();
    if (report.predicted) {
        anderson_.continue_history();
    } else {
        anderson_.restart();
    }
    return paper_iterations(report, control, 0, std::numeric_limits<double>::infinity(), start);
}

Status DeformSession::resume(SolveReport& report, const Control* control) {
    if (!paused_.active) return Status(Errc::invalid_argument, "no solve is paused");
    paused_.active = false;
    report = paused_.report;
    report.paused = false;
    const auto start = std::chrono::steady_clock::now() -
                       std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                           std::chrono::duration<double, std::milli>(paused_.elapsed_ms));
    return settings_.method == DeformMethod::fitted_rotations
               ? fitted_iterations(report, control, paused_.iteration, paused_.carried, start)
               : paper_iterations(report, control, paused_.iteration, paused_.carried, start);
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

Status DeformSession::paper_iterations(SolveReport& report, const Control* control, int first,
                                       double smallest_update,
                                       std::chrono::steady_clock::time_point start) {
    const std::atomic<bool>* interrupt = control != nullptr ? control->interrupt : nullptr;
    const double diag = model_.diagonal > 0.0 ? model_.diagonal : 1.0;
    for (int it = first; it < settings_.max_iterations; ++it) {
        if (it > 0 && interrupt != nullptr && interrupt->load(std::memory_order_acquire)) {
            report.interrupted = true;
            report.solve_ms = ms_since(start);
            return Status::ok();
        }
        if (pause_before(it, first, smallest_update, start, control, report)) return Status::ok();
        auto phase = std::chrono::steady_clock::now();
        compute_dual_targets();
        report.normals_ms += ms_since(phase);
        phase = std::chrono::steady_clock::now();
        compute_right_hand_side();
        report.rhs_ms += ms_since(phase);
        phase = std::chrono::steady_clock::now();
        std::size_t krylov = 0;
        if (Status s = linear_.solve(rhs_, x_, settings_.linear_tolerance * diag,
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
            store_solution();
            report.converged = true;
            break;
        }
        // The extrapolated iterates are not monotone, and restarting at every
        // growth stalls them (measured on the whole cow); a step more than
        // twice the smallest so far means the history has gone astray.
        phase = std::chrono::steady_clock::now();
        if (report.last_update > 2.0 * smallest_update) anderson_.restart();
        smallest_update = std::min(smallest_update, report.last_update);
        anderson_.step(current_, x_, next_);
        report.anderson_ms += ms_since(phase);
        std::copy(next_.begin(), next_.end(), current_.begin());
        std::copy(next_.begin(), next_.end(), x_.begin());
        store_solution();
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
    // step, finite and already stored, stands.
    std::copy(x_.begin(), x_.end(), next_.begin());
    std::size_t krylov = 0;
    const auto verify_start = std::chrono::steady_clock::now();
    const Status verified = linear_.solve(rhs_, x_, settings_.linear_tolerance * diag,
                                          LinearSolver::Accuracy::verified, krylov);
    report.linear_ms += ms_since(verify_start);
    report.krylov_iterations += krylov;
    report.linear_converged = verified.is_ok() && linear_.converged();
    if (report.linear_converged) {
        report.linear_residual = linear_.relative_residual();
        store_solution();
    } else {
        report.linear_residual = std::numeric_limits<double>::quiet_NaN();
        std::copy(next_.begin(), next_.end(), x_.begin());
    }
    if (report.converged) predictor_.record(x_, targets_);
}

}  // namespace dfm::deform
