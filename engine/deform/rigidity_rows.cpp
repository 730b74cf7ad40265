#include "deform/rigidity_rows.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstring>

#include <glm/geometric.hpp>
#include <glm/gtx/quaternion.hpp>

#include "core/simd.hpp"
#include "deform/rotation_fit_lanes.hpp"

// The pass over the rows is also compiled for AVX2 and for AVX-512 (its 32
// registers hold more of the four lanes' fit; the lanes stay four doubles)
// and picked at run time where the processor has them, as the solver's
// dense kernels are: the same multiplications and additions in the same
// order (no fused multiply–add), so the same bits, in fewer instructions
// (where DFM_X86_DISPATCH).

namespace dfm::deform {

namespace {

constexpr std::size_t slots = RigidityStencil::slots;
constexpr std::size_t pairs = RigidityStencil::pairs;

// The vertex of triangle `t` that is not on the edge it shares with `other`.
std::uint32_t opposite_vertex(const mesh::Triangle& t, const mesh::Triangle& other) {
    for (std::uint32_t v : t) {
        if (v != other[0] && v != other[1] && v != other[2]) return v;
    }
    return mesh::no_index;
}

// The face edges' rows against the dual edges' for an edge of mean length.
// A face edge's row weighs its relative change, so a short edge squeezed
// next to a handle costs what a long one does: at 0.2 a hoof pushed into
// its leg turned a ring of faces over at the handle's rim (the camel's 71),
// at 0.95 (rigidity_weight 0.04) none; the relative weight also keeps the
// camel head's needles, whose turning over changes no length by much, from
// turning over (docs/method.md).
constexpr double relative_edge_weight = 0.95;

// In the surface's order (row_order.hpp) the rows' faces lie anywhere in
// the mesh's arrays: the set-up fetches a row's face 2 · build_ahead rows
// before it makes the row's stencil, and its neighbours' corners and its
// own corners' positions build_ahead rows before.
constexpr std::size_t build_ahead = 8;

}  // namespace

double balanced_rigidity_weight(std::size_t unknowns) {
    const double ratio = static_cast<double>(balance_unknowns) /
                         static_cast<double>(std::max<std::size_t>(unknowns, 1));
    return rigidity_weight * std::sqrt(std::min(1.0, ratio));
}

void RotationFrames::build(const MeshModel& model, const UnknownMap& unknowns,
                           const SystemRows& rows, const RotationClusters& clusters) {
    const mesh::Mesh& mesh = model.mesh;
    const double weight = balanced_rigidity_weight(unknowns.count());
    const std::size_t dual_rows = rows.size();
    // Edge rows are relative: a needle's short edge gets the weight of its
    // shortness. Lengths alone would let needles (the camel's head has edges
    // 70 times shorter than their neighbours) turn over at no cost.
    double mean_edge = 0.0;
    for (const auto& e : model.topology.edges) {
        mean_edge += glm::length(mesh.positions[e[0]] - mesh.positions[e[1]]);
    }
    mean_edge /= static_cast<double>(std::max<std::size_t>(model.topology.edges.size(), 1));

    // The local step's numbering: the unknowns', then the fixed vertices
    // in the order the rows first reach them.
    const auto unknown_count = static_cast<std::uint32_t>(unknowns.count());
    std::vector<std::uint32_t> fixed_local(mesh.vertex_count(), mesh::no_index);
    fixed_vertices_.clear();
    const auto local_of = [&](std::uint32_t v) {
        if (unknowns.unknown_of_vertex[v] != mesh::no_index) return unknowns.unknown_of_vertex[v];
        if (fixed_local[v] == mesh::no_index) {
            fixed_local[v] = unknown_count + static_cast<std::uint32_t>(fixed_vertices_.size());
            fixed_vertices_.push_back(v);
        }
        return fixed_local[v];
    };

    // Each stencil is made on the stack and written once: filling a
    // zeroed array would write its bytes twice.
    stencils_.clear();
    stencils_.reserve(dual_rows);
    fixed_.clear();
    for (std::size_t r = 0; r < dual_rows; ++r) {
        if (r + 2 * build_ahead < dual_rows) {
            const std::uint32_t later = rows.faces[r + 2 * build_ahead];
            __builtin_prefetch(&mesh.triangles[later]);
            __builtin_prefetch(&model.dual.neighbors[later]);
            __builtin_prefetch(&model.dual.weights[later]);
        }
        if (r + build_ahead < dual_rows) {
            const std::uint32_t next = rows.faces[r + build_ahead];
            for (const std::uint32_t j : model.dual.neighbors[next])
                if (j != mesh::no_index) __builtin_prefetch(&mesh.triangles[j]);
            for (const std::uint32_t v : mesh.triangles[next])
                __builtin_prefetch(&mesh.positions[v]);
        }
        RigidityStencil s;
        const std::uint32_t f = rows.faces[r];
        const mesh::Triangle& t = mesh.triangles[f];
        const glm::dvec3 rest_dual = dual::dual_coordinate_at(mesh, model.dual, mesh.positions, f);
        s.rest_dual2 = glm::dot(rest_dual, rest_dual);
        // The coefficients b_ki of every row of this dual row, by slot.
        std::array<std::array<double, slots>, pairs + 1> b{};
        std::size_t used = 0;
        for (std::uint32_t p = rows.entry_offsets[r]; p < rows.entry_offsets[r + 1]; ++p) {
            const RowEntry& e = rows.entries[p];
            s.vertex[used] = local_of(e.vertex);
            s.dual[used] = e.coefficient;
            b[0][used] = e.coefficient;
            ++used;
        }
        s.slot_count = static_cast<std::uint8_t>(used);
        for (std::size_t i = used; i < slots; ++i) s.vertex[i] = s.vertex[0];
        // A rigidity row joins two vertices of f's dual 1-ring, which are
        // all in the dual row: w s (v_c − v_d), for its rest vector.
        auto slot_of = [&](std::uint32_t v) {
            const std::uint32_t local = local_of(v);
            std::size_t i = 0;
            while (i + 1 < used && s.vertex[i] != local) ++i;
            return static_cast<std::uint8_t>(i);
        };
        auto add_pair = [&](std::uint32_t c, std::uint32_t d, double scale) {
            if (unknowns.unknown_of_vertex[c] == mesh::no_index &&
                unknowns.unknown_of_vertex[d] == mesh::no_index)
                return;
            const double cc = weight * scale;
            const double dc = -weight * scale;
            const glm::dvec3 rest_vector = weight * scale * (mesh.positions[c] - mesh.positions[d]);
            const std::size_t k = s.pair_count++;
            const std::uint8_t sc = slot_of(c);
            const std::uint8_t sd = slot_of(d);
            s.pair_slot[k] = {sc, sd};
            s.pair_weight2[k] = cc * cc;
            s.pair_target2 += glm::dot(rest_vector, rest_vector);
            for (int x = 0; x < 3; ++x) {
                s.g[x][sc] += cc * rest_vector[x];
                s.g[x][sd] += dc * rest_vector[x];
            }
            b[k + 1][sc] += cc;
            b[k + 1][sd] += dc;
        };
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t j = model.dual.neighbors[f][k];
            const std::uint32_t c = opposite_vertex(t, mesh.triangles[j]);
            const std::uint32_t d = opposite_vertex(mesh.triangles[j], t);
            if (c != mesh::no_index && d != mesh::no_index) add_pair(c, d, 1.0 / 3.0);
            const std::uint32_t a = t[k];
            const std::uint32_t e = t[(k + 1) % 3];
            const double length = glm::length(mesh.positions[a] - mesh.positions[e]);
            if (length > 0.0) add_pair(a, e, relative_edge_weight * mean_edge / length);
        }
        // The dual row's own target, l_f, pulled to each slot: every fit
        // needs G_i whole, and it does not change.
        for (int x = 0; x < 3; ++x) {
            for (std::size_t i = 0; i < slots; ++i)
                s.g[x][i] = s.g[x][i] + s.dual[i] * rest_dual[x];
        }
        for (std::size_t i = 0; i < used; ++i) {
            const std::uint32_t u = slot_unknown(s, i, unknown_count);
            if (u == mesh::no_index) continue;
            for (std::size_t j = 0; j < used; ++j) {
                if (slot_unknown(s, j, unknown_count) != mesh::no_index) continue;
                double coupling = 0.0;
                for (const auto& row : b) coupling += row[i] * row[j];
                if (coupling != 0.0) fixed_.push_back({u, s.vertex[j], -coupling});
            }
        }
        stencils_.push_back(s);
    }
    // The same pair comes from every dual row that holds both: one term each.
    std::sort(fixed_.begin(), fixed_.end(), [](const FixedCoupling& x, const FixedCoupling& y) {
        return x.unknown != y.unknown ? x.unknown < y.unknown : x.vertex < y.vertex;
    });
    std::size_t merged = 0;
    for (std::size_t k = 0; k < fixed_.size(); ++k) {
        if (merged > 0 && fixed_[merged - 1].unknown == fixed_[k].unknown &&
            fixed_[merged - 1].vertex == fixed_[k].vertex) {
            fixed_[merged - 1].coefficient += fixed_[k].coefficient;
        } else {
            fixed_[merged++] = fixed_[k];
        }
    }
    fixed_.resize(merged);
    local_.resize(unknown_count + fixed_vertices_.size());

    // A two-thread fit's halves (fit_and_add): the second half's slots at
    // unknowns the first half names.
    half_ = dual_rows / 2 - dual_rows / 2 % fit_lanes::width;
    shared_below_ = 0;
    for (std::size_t r = 0; r < half_; ++r) {
        for (std::size_t i = 0; i < slots; ++i) {
            const std::uint32_t u = slot_unknown(stencils_[r], i, unknown_count);
            if (u != mesh::no_index) shared_below_ = std::max(shared_below_, u + 1);
        }
    }
    shared_unknowns_.clear();
    for (std::size_t r = half_; r < dual_rows; ++r) {
        for (std::size_t i = 0; i < slots; ++i) {
            const std::uint32_t u = slot_unknown(stencils_[r], i, unknown_count);
            if (u < shared_below_) shared_unknowns_.push_back(u);
        }
    }
    kept_.assign(dual_rows, glm::dquat(1.0, 0.0, 0.0, 0.0));
    fitted_ = kept_;

    build_coarse_field(clusters);
}

std::size_t RotationFrames::rigidity_rows() const {
    std::size_t count = 0;
    for (const RigidityStencil& s : stencils_) count += s.pair_count;
    return count;
}

namespace {

struct FitPass {
    std::span<const RigidityStencil> stencils;
    std::span<const glm::dquat> kept;
    std::span<glm::dquat> fitted;
    // Per row: its heaviest cluster, no_index for a row no cluster reaches,
    // whose own rotation takes its whole target.
    std::span<const std::uint32_t> heaviest;
    std::span<const glm::dquat> cluster_rotations;  // the clusters' fits, as quaternions
    std::span<const glm::dvec3> positions;          // in the local step's numbering
    std::uint32_t unknowns;                         // below it, a number is an unknown's
    int steps;
    std::span<double> rhs;
    // Null: each row adds its share to rhs and the pass returns the energy.
    // Otherwise a row keeps its energy here, and its share at an unknown
    // below `shared_below` in `shares`, 3 doubles after the last, for the
    // caller to add in order; it adds its other shares itself.
    double* energies = nullptr;
    std::uint32_t shared_below = 0;
    double* shares = nullptr;
};

// Two doubles, the width every x86-64 processor has: the slots go three
// pairs at a time, in registers.
using simd::Doubles2;
constexpr std::size_t lanes = slots / simd::lanes<Doubles2>;
using SlotLanes = std::array<Doubles2, lanes>;

[[gnu::always_inline]] inline Doubles2 lanes_at(const double* a) {
    Doubles2 v;
    std::memcpy(&v, a, sizeof v);
    return v;
}

[[gnu::always_inline]] inline double lane_sum(const Doubles2& v) {
    return v[0] + v[1];
}

// Gathers dual row r's positions, fills lane `lane` of the covariance and
// returns |A_k p|² summed over the row's rows, which the fit does not change.
[[gnu::always_inline]] inline double prepare_row(const FitPass& pass, std::size_t r,
                                                 std::size_t lane, fit_lanes::Mat3& covariance) {
    const RigidityStencil& s = pass.stencils[r];
    // The lanes are loaded from the positions themselves: a copy of them
    // on the stack, read back in other pairs, stalls each load on the
    // stores it spans.
    std::array<SlotLanes, 3> p;  // by coordinate
    for (std::size_t l = 0; l < lanes; ++l) {
        const glm::dvec3& u = pass.positions[s.vertex[2 * l]];
        const glm::dvec3& w = pass.positions[s.vertex[2 * l + 1]];
        p[0][l] = Doubles2{u.x, w.x};
        p[1][l] = Doubles2{u.y, w.y};
        p[2][l] = Doubles2{u.z, w.z};
    }
    // |A_k p|² does not depend on the fit: taken before it.
    double rows2 = 0.0;
    std::array<SlotLanes, 3> g;
    std::array<SlotLanes, 3> e;
    for (std::size_t x = 0; x < 3; ++x) {
        Doubles2 product = lanes_at(&s.dual[0]) * p[x][0];
        for (std::size_t l = 1; l < lanes; ++l) product += lanes_at(&s.dual[2 * l]) * p[x][l];
        const double dual = lane_sum(product);
        rows2 += dual * dual;
        const double origin = p[x][0][0];
        for (std::size_t l = 0; l < lanes; ++l) {
            g[x][l] = lanes_at(&s.g[x][2 * l]);
            // Σ_i G_i = 0 (every row's coefficients sum to zero):
            // positions relative to the first slot give the same
            // covariance, with less cancellation.
            e[x][l] = p[x][l] - origin;
        }
    }
    for (std::size_t k = 0; k < pairs; ++k) {
        const glm::dvec3 edge = pass.positions[s.vertex[s.pair_slot[k][0]]] -
                                pass.positions[s.vertex[s.pair_slot[k][1]]];
        rows2 += s.pair_weight2[k] * glm::dot(edge, edge);
    }
    for (int row = 0; row < 3; ++row) {
        for (int column = 0; column < 3; ++column) {
            Doubles2 sum = e[row][0] * g[column][0];
            for (std::size_t l = 1; l < lanes; ++l) sum += e[row][l] * g[column][l];
            covariance.m[column][row][lane] = lane_sum(sum);
        }
    }
    return rows2;
}

// Adds dual row r's own share of Aᵀ t, its own rotation's share of its
// target rotation times G_i, to the right-hand side (or keeps it at
// `shares`, FitPass's); returns its energy but for the clusters' alignment
// (fit_and_add's).
[[gnu::always_inline]] inline double finish_row(const FitPass& pass, std::size_t r,
                                                std::size_t lane, const fit_lanes::Mat3& rotation,
                                                double alignment, double rows2, double*& shares) {
    const RigidityStencil& s = pass.stencils[r];
    const double own = pass.heaviest[r] == mesh::no_index ? 1.0 : 1.0 - coarse_share;
    std::array<SlotLanes, 3> pull;  // own R_f G_i by coordinate
    for (int x = 0; x < 3; ++x) {
        const double r0 = own * rotation.m[0][x][lane];
        const double r1 = own * rotation.m[1][x][lane];
        const double r2 = own * rotation.m[2][x][lane];
        for (std::size_t l = 0; l < lanes; ++l) {
            pull[x][l] = r0 * lanes_at(&s.g[0][2 * l]) + r1 * lanes_at(&s.g[1][2 * l]) +
                         r2 * lanes_at(&s.g[2][2 * l]);
        }
    }
    const double energy = rows2 - 2.0 * own * alignment + s.rest_dual2 + s.pair_target2;
    for (std::size_t i = 0; i < slots; ++i) {
        const std::uint32_t u = slot_unknown(s, i, pass.unknowns);
        if (u == mesh::no_index) continue;
        if (u < pass.shared_below) {
            for (std::size_t x = 0; x < 3; ++x) shares[x] = pull[x][i / 2][i % 2];
            shares += 3;
            continue;
        }
        double* out = &pass.rhs[3 * u];
        out[0] += pull[0][i / 2][i % 2];
        out[1] += pull[1][i / 2][i % 2];
        out[2] += pull[2][i / 2][i % 2];
    }
    if (pass.energies != nullptr) {
        pass.energies[r] = energy;
        return 0.0;
    }
    return energy;
}

// The kept rotations of four rows, one lane each: each quaternion loaded
// whole and the four turned into vectors by component. Set lane by lane,
// through memory, each vector's load waited on the four stores it spans.
[[gnu::always_inline]] inline fit_lanes::Quat kept_lanes(
    std::span<const glm::dquat> kept, const std::array<std::size_t, fit_lanes::width>& row) {
    static_assert(fit_lanes::width == 4 && sizeof(glm::dquat) == sizeof(fit_lanes::Quad) &&
                  offsetof(glm::dquat, x) == 0 && offsetof(glm::dquat, y) == 8 &&
                  offsetof(glm::dquat, z) == 16 && offsetof(glm::dquat, w) == 24);
    fit_lanes::Quad k[fit_lanes::width];
    for (std::size_t lane = 0; lane < fit_lanes::width; ++lane)
        std::memcpy(&k[lane], &kept[row[lane]], sizeof(fit_lanes::Quad));
    const fit_lanes::Quad xz01 = __builtin_shufflevector(k[0], k[1], 0, 4, 2, 6);
    const fit_lanes::Quad yw01 = __builtin_shufflevector(k[0], k[1], 1, 5, 3, 7);
    const fit_lanes::Quad xz23 = __builtin_shufflevector(k[2], k[3], 0, 4, 2, 6);
    const fit_lanes::Quad yw23 = __builtin_shufflevector(k[2], k[3], 1, 5, 3, 7);
    fit_lanes::Quat q;
    q.x = __builtin_shufflevector(xz01, xz23, 0, 1, 4, 5);
    q.z = __builtin_shufflevector(xz01, xz23, 2, 3, 6, 7);
    q.y = __builtin_shufflevector(yw01, yw23, 0, 1, 4, 5);
    q.w = __builtin_shufflevector(yw01, yw23, 2, 3, 6, 7);
    return q;
}

// Four dual rows at a time, their rotations fitted side by side in the
// lanes of one vector (rotation_fit_lanes.hpp); the right-hand side and
// the energy still take the rows one by one, in order.
[[gnu::always_inline]] inline double fit_rows_body(const FitPass& pass) {
    constexpr std::size_t width = fit_lanes::width;
    double energy = 0.0;
    double* shares = pass.shares;
    const std::size_t count = pass.stencils.size();
    for (std::size_t first = 0; first < count; first += width) {
        const std::size_t used = std::min(width, count - first);
        // The stencils stream in order, the positions they name only near
        // it: the rows two groups ahead are fetched, and the positions of
        // those one group ahead.
        if (first + 3 * width <= count) {
            const auto* ahead = reinterpret_cast<const char*>(&pass.stencils[first + 2 * width]);
            for (std::size_t byte = 0; byte < width * sizeof(RigidityStencil); byte += 64)
                __builtin_prefetch(ahead + byte);
        }
        if (first + 2 * width <= count) {
            for (std::size_t r = first + width; r < first + 2 * width; ++r)
                for (const std::uint32_t v : pass.stencils[r].vertex)
                    __builtin_prefetch(&pass.positions[v]);
        }
        fit_lanes::Mat3 covariance;
        std::array<double, width> rows2;
        // Past the last row, a lane repeats the first: its result is
        // dropped, and it stops when that row's fit does.
        std::array<std::size_t, width> row;
        for (std::size_t lane = 0; lane < width; ++lane) {
            row[lane] = first + (lane < used ? lane : 0);
            rows2[lane] = prepare_row(pass, row[lane], lane, covariance);
        }
        fit_lanes::Quat q = kept_lanes(pass.kept, row);
        if (pass.steps > 1) {
            // A solve's first fit may start far from the answer, and a row
            // fitted alone from there can stop at a saddle of its alignment,
            // where its cluster's many rows leave none (a whole cow turned
            // by 60°): each row starts from its own kept rotation or its
            // heaviest cluster's, whichever aligns it better.
            fit_lanes::Quat cluster = q;
            for (std::size_t lane = 0; lane < width; ++lane) {
                const std::size_t r = first + (lane < used ? lane : 0);
                if (pass.heaviest[r] == mesh::no_index) continue;
                const glm::dquat& c = pass.cluster_rotations[pass.heaviest[r]];
                cluster.w[lane] = c.w;
                cluster.x[lane] = c.x;
                cluster.y[lane] = c.y;
                cluster.z[lane] = c.z;
            }
            fit_lanes::Mat3 own_start;
            fit_lanes::Mat3 cluster_start;
            fit_lanes::rotation_of(q, own_start);
            fit_lanes::rotation_of(cluster, cluster_start);
            fit_lanes::select(fit_lanes::alignment(cluster_start, covariance) >
                                  fit_lanes::alignment(own_start, covariance),
                              cluster, q);
        }
        fit_lanes::Mat3 rotation;
        fit_lanes::Quad alignment;
        fit_rotations(covariance, q, pass.steps, rotation, alignment);
        for (std::size_t lane = 0; lane < used; ++lane) {
            const std::size_t r = first + lane;
            pass.fitted[r] = glm::dquat(q.w[lane], q.x[lane], q.y[lane], q.z[lane]);
            energy += finish_row(pass, r, lane, rotation, alignment[lane], rows2[lane], shares);
        }
    }
    return energy;
}

double fit_rows_plain(const FitPass& pass) {
    return fit_rows_body(pass);
}

#if DFM_X86_DISPATCH
DFM_TARGET_AVX2 double fit_rows_avx2(const FitPass& pass) {
    return fit_rows_body(pass);
}

DFM_TARGET_AVX512 double fit_rows_avx512(const FitPass& pass) {
    return fit_rows_body(pass);
}
#endif

double fit_rows(const FitPass& pass) {
#if DFM_X86_DISPATCH
    if (simd::widest() == simd::Set::avx512) return fit_rows_avx512(pass);
    if (simd::widest() == simd::Set::avx2) return fit_rows_avx2(pass);
#endif
    return fit_rows_plain(pass);
}

}  // namespace

double RotationFrames::fit_and_add(std::span<const double> x, std::span<const glm::dvec3> positions,
                                   int steps, std::span<double> rhs, jobs::WorkerPool* pool) {
    const std::size_t unknowns = local_.size() - fixed_vertices_.size();
    std::memcpy(local_.data(), x.data(), unknowns * sizeof(glm::dvec3));
    for (std::size_t k = 0; k < fixed_vertices_.size(); ++k)
        local_[unknowns + k] = positions[fixed_vertices_[k]];
    const std::span<const glm::dvec3> local = local_;
    for (const FixedCoupling& c : fixed_) {
        const glm::dvec3& p = local[c.vertex];
        double* out = &rhs[3 * c.unknown];
        out[0] += c.coefficient * p.x;
        out[1] += c.coefficient * p.y;
        out[2] += c.coefficient * p.z;
    }

    // The clusters first: a solve's first fit starts a row from its
    // cluster's rotation where that aligns it better.
    const double cluster_alignment = fit_clusters(steps);
    const std::size_t count = stencils_.size();
    const auto unknown_count = static_cast<std::uint32_t>(unknowns);
    const FitPass whole{stencils_, kept_,         fitted_, heaviest_, cluster_fitted_,
                        local,     unknown_count, steps,   rhs};
    double energy = 0.0;
    if (pool == nullptr || pool->thread_count() < 2 || count < jobs::parallel_minimum) {
        energy = fit_rows(whole);
    } else {
        // Two halves side by side. The first half adds only below
        // shared_below_ and adds as it goes; above it only the second half
        // adds, which it does as it goes too, and below it the second half
        // keeps its shares, which are then added after the first half's, as
        // are its energies, in order: the sums of the one-thread pass, bit
        // for bit.
        const auto part = [&](std::size_t begin, std::size_t end) {
            return FitPass{std::span(stencils_).subspan(begin, end - begin),
                           std::span(kept_).subspan(begin, end - begin),
                           std::span(fitted_).subspan(begin, end - begin),
                           std::span(heaviest_).subspan(begin, end - begin),
                           cluster_fitted_,
                           local,
                           unknown_count,
                           steps,
                           rhs};
        };
        shared_shares_.resize(3 * shared_unknowns_.size());
        second_energies_.resize(count - half_);
        pool->run(2, [&](std::size_t task) {
            if (task == 0) {
                energy = fit_rows(part(0, half_));
            } else {
                FitPass second = part(half_, count);
                second.energies = second_energies_.data();
                second.shared_below = shared_below_;
                second.shares = shared_shares_.data();
                fit_rows(second);
            }
        });
        for (std::size_t k = 0; k < shared_unknowns_.size(); ++k) {
            double* out = &rhs[3 * shared_unknowns_[k]];
            out[0] += shared_shares_[3 * k];
            out[1] += shared_shares_[3 * k + 1];
            out[2] += shared_shares_[3 * k + 2];
        }
        for (const double e : second_energies_) energy += e;
    }

    add_cluster_shares(rhs);
    return energy - 2.0 * cluster_alignment;
}

}  // namespace dfm::deform
