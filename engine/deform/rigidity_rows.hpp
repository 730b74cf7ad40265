#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include <glm/gtc/quaternion.hpp>

#include "core/memory_bytes.hpp"
#include "core/pooled_allocator.hpp"
#include "deform/mesh_model.hpp"
#include "deform/normal_system.hpp"
#include "deform/rotation_clusters.hpp"
#include "jobs/worker_pool.hpp"

// The default method's local step (docs/method.md). Each dual row f gets a
// rotation R_f fitted to its dual 1-ring, and its rows follow it: the dual
// Laplacian row asks for R_f l_f (the rest coordinate turned, where the paper
// takes the plane normal), and rigidity rows ask each dual edge c_f − c_j
// and each edge of f to equal R_f times its rest vector. The dual Laplacian
// rows keep the detail; the rigidity rows keep the lengths that those rows
// leave free, so a large bend turns the surface instead of folding it. As f
// and j share an edge, c_f − c_j = (v_c − v_d) / 3 for the two vertices
// opposite it: every rigidity row has two entries inside the dual rows'
// 2-ring, and the normal matrix keeps its sparsity pattern.
namespace dfm::deform {

// One dual row and its rigidity rows, over its own vertices. Every row
// is linear in the slots' positions, A_k p = Σ_i b_ki p_i, with a target
// R_f g_k: so the covariance is Σ_i p_i G_iᵀ and the rows' share of
// Aᵀ t at slot i is R_f G_i, for G_i = Σ_k b_ki g_k; and their energy
// Σ_k |A_k p − R_f g_k|² = Σ_k |A_k p|² − 2 tr(R_fᵀ C) + Σ_k |g_k|², its
// middle term the fit's own alignment. Unused slots and pairs have zero
// coefficients. G_i is kept by coordinate so that its loops vectorise.
// The slots' vertices are numbered as the local step reads them
// (RotationFrames): an unknown by its number, the k-th fixed vertex the
// rows reach as the unknowns' count plus k; so a slot's number tells
// whether it is an unknown (slot_unknown).
struct RigidityStencil {
    static constexpr std::size_t slots = 6;  // a dual row's vertices: f's and the three opposite
    static constexpr std::size_t pairs = 6;  // rigidity rows per dual row: 3 dual, 3 face edges

    // What the assembly of N reads comes first and together (vertex to
    // slot_count), so that each of a stencil's several reads there, out of
    // order, takes as few cache lines as the fields allow.
    std::array<std::uint32_t, slots> vertex{};  // in the local step's numbering
    std::array<double, slots> dual{};           // the dual row's coefficients
    std::array<double, pairs> pair_weight2{};   // (w s)²: A_k p = w s (v_c − v_d)
    std::array<std::array<std::uint8_t, 2>, pairs> pair_slot{};  // the slots of v_c, v_d
    std::uint8_t pair_count = 0;                   // the rows in use, in their order in A
    std::uint8_t slot_count = 0;                   // the slots in use, the first ones
    std::array<std::array<double, slots>, 3> g{};  // G_i, of the dual row and its rigidity rows
    double rest_dual2 = 0.0;                       // |l_f|² at rest
    double pair_target2 = 0.0;                     // Σ_k |g_k|² over the rigidity rows
};

// Slot i's unknown in a ROI of `unknowns` unknowns: its vertex's number, or
// no_index for a fixed vertex and an unused slot.
inline std::uint32_t slot_unknown(const RigidityStencil& s, std::size_t i, std::uint32_t unknowns) {
    return i < s.slot_count && s.vertex[i] < unknowns ? s.vertex[i] : mesh::no_index;
}

// ROIs of more unknowns than this take a rigidity weight smaller by the
// square root of the ratio. Under a strain, a dual Laplacian row's residual
// scales as h² (h the edge length) and a rigidity row's as h, so at a fixed
// weight the finer mesh is the stiffer one: with the weight proportional to
// h over the ROI's size, the same edit keeps its shape and its iteration
// count at every level of detail. Smaller ROIs keep the weight, which was
// tuned on them (docs/method.md).
inline constexpr std::size_t balance_unknowns = 2500;

// The rigidity rows' weight against the dual Laplacian rows for a ROI of up
// to balance_unknowns unknowns. More keeps lengths closer to ARAP's and
// loses detail (the dual magnitude error and the normal change rise): 0.04,
// with the face edges at relative_edge_weight, kept the detail of the
// previous 0.1 (face edges 0.2) on every limb of the quality table while
// its compressive pushes stopped folding (docs/method.md).
inline constexpr double rigidity_weight = 0.04;

// rigidity_weight balanced for a ROI of `unknowns` unknowns.
double balanced_rigidity_weight(std::size_t unknowns);

// The share θ of every row's target rotation that comes from the coarse
// field (rotation_clusters.hpp); the rest is the row's own fit. Half and
// half kept the limbs' bends and twists within a few percent of the rows'
// own rotations while the whole armadillo converged in half the iterations
// and compressive pushes folded far less. θ is a term of the energy, not an
// accelerator: the fixed point depends on it, and at θ = 0 the pushes'
// minimisers fold (docs/method.md, "What the iteration converges to").
inline constexpr double coarse_share = 0.5;

// The clusters of the coarse rotation field over the dual rows of `rows`
// (those that touch an unknown), neighbours across the dual edges.
RotationClusters coarse_clusters(const MeshModel& model, const SystemRows& rows);

class RotationFrames {
public:
    // Makes the rigidity rows of each dual row of `rows` (those that touch
    // an unknown), weighted by balanced_rigidity_weight against
    // the dual Laplacian rows, takes `clusters` (coarse_clusters of the
    // same rows) for the coarse field, and starts every rotation at the
    // identity. A's rows are the dual rows in their order, then each dual
    // row's rigidity rows in turn.
    void build(const MeshModel& model, const UnknownMap& unknowns, const SystemRows& rows,
               const RotationClusters& clusters);

    // N = AᵀA + w² H + ε I over A's rows, each entry summed in A's row
    // order (the bits of assemble_normal_matrix over the same rows), with
    // the arguments of assemble_normal_matrix.
    solver::CsrMatrix assemble_normal_matrix(std::size_t unknown_count,
                                             std::span<const std::uint32_t> soft_handles,
                                             double handle_weight, double relative_epsilon,
                                             double& epsilon,
                                             const std::atomic<bool>* stop = nullptr) const;

    // The local step, and the global step's right-hand side: fits each dual
    // row's own rotation R_f and each cluster's rotation R_c to the unknowns
    // at `x` (3 interleaved columns) and the fixed vertices at `positions`
    // (the whole mesh), starting from the last kept fits (keep_fit) with at
    // most `steps` Newton steps, then adds Aᵀ (t − A_fixed p_fixed) to rhs
    // (3 interleaved columns; write_handle_terms starts it) for the rows'
    // targets t, and returns the rows' share of the energy
    // (deform_energy.hpp):
    //   Σ_f (1 − θ) |rows_f(p) − R_f g_f|² + θ Σ_c κ_fc |rows_f(p) − R_c g_f|²,
    // θ the coarse field's share and κ_fc row f's weight in cluster c; each
    // row's target rotation is then (1 − θ) R_f + θ Σ_c κ_fc R_c. A fit
    // never raises the energy over the kept rotations.
    // With `pool` (optional) of two threads or more, a large ROI's rows are
    // fitted in two halves side by side, with the same bits.
    double fit_and_add(std::span<const double> x, std::span<const glm::dvec3> positions, int steps,
                       std::span<double> rhs, jobs::WorkerPool* pool = nullptr);

    // Makes the last fit the next one's starting point. A refused trial step
    // is not kept: the next fit starts again from the rotations before it.
    void keep_fit() {
        kept_.swap(fitted_);
        cluster_kept_.swap(cluster_fitted_);
    }

    std::size_t dual_rows() const { return stencils_.size(); }
    std::size_t rigidity_rows() const;
    std::size_t memory_bytes() const {
        return capacity_bytes(stencils_, fixed_, fixed_vertices_, local_, kept_, fitted_,
                              shared_unknowns_, shared_shares_, second_energies_, heaviest_,
                              patch_offsets_, patch_pulls_, member_offsets_, members_,
                              cluster_kept_, cluster_fitted_, cluster_rotations_, cluster_sums_);
    }

private:
    // coarse_rotations.cpp: the patches' sums over their rows, the
    // clusters' rotations fitted to local_ (returns Σ_c tr(R_cᵀ θ A_c)),
    // and their shares of the right-hand side.
    void build_coarse_field(const RotationClusters& clusters);
    double fit_clusters(int steps);
    void add_cluster_shares(std::span<double> rhs) const;

    // −(Aᵀ A)_uv between an unknown u and a fixed vertex v: the fixed
    // vertices' share of the right-hand side, −Σ (Aᵀ A)_uv p_v.
    struct FixedCoupling {
        std::uint32_t unknown;
        std::uint32_t vertex;  // in the local step's numbering
        double coefficient;
    };

    PooledVector<RigidityStencil> stencils_;  // per dual row
    std::vector<FixedCoupling> fixed_;
    // The local step's numbering (RigidityStencil): the fixed vertices'
    // numbers in the mesh, and the positions of all, the unknowns' copied
    // from the iterate at each fit. In the unknowns' order, which follows
    // the surface (row_order.hpp), the rows' reads stay near each other.
    std::vector<std::uint32_t> fixed_vertices_;
    UnzeroedPooledVector<glm::dvec3> local_;
    PooledVector<glm::dquat> kept_;    // per dual row: the fit the next one starts from
    PooledVector<glm::dquat> fitted_;  // per dual row: the last fit
    // A two-thread fit (fit_and_add): the second half's first row; one
    // past the largest unknown the first half names; the unknown of each
    // of the second half's slots below that, in order, and the shares a
    // fit keeps for them; the second half's energies.
    std::size_t half_ = 0;
    std::uint32_t shared_below_ = 0;
    std::vector<std::uint32_t> shared_unknowns_;
    std::vector<double> shared_shares_;
    std::vector<double> second_energies_;
    // A patch's rows at vertex `vertex`: H_pv = Σ_{f ∈ patch} G_f,slot(v)
    // (build's comment).
    struct PatchPull {
        std::uint32_t vertex;  // in the local step's numbering: an unknown below their count
        glm::dvec3 pulled;
    };
    // A patch's share of a cluster's rotation: θ κ_pc.
    struct Member {
        std::uint32_t cluster;
        double share;
    };
    std::span<const PatchPull> patch_pulls(std::size_t p) const {
        return std::span(patch_pulls_)
            .subspan(patch_offsets_[p], patch_offsets_[p + 1] - patch_offsets_[p]);
    }
    std::span<const Member> patch_members(std::size_t p) const {
        return std::span(members_).subspan(member_offsets_[p],
                                           member_offsets_[p + 1] - member_offsets_[p]);
    }

    // Per dual row: its patch's heaviest cluster (no_index: none reaches it).
    std::vector<std::uint32_t> heaviest_;
    std::vector<std::uint32_t> patch_offsets_;   // per patch, into patch_pulls_
    std::vector<PatchPull> patch_pulls_;         // by patch, then vertex
    std::vector<std::uint32_t> member_offsets_;  // per patch, into members_
    std::vector<Member> members_;                // by patch, in cluster order
    std::vector<glm::dquat> cluster_kept_;       // per cluster, as kept_
    std::vector<glm::dquat> cluster_fitted_;     // per cluster, as fitted_
    std::vector<glm::dmat3> cluster_rotations_;  // per cluster: the last fit's rotation
    std::vector<glm::dmat3> cluster_sums_;       // per cluster: scratch of the local step
};

}  // namespace dfm::deform
