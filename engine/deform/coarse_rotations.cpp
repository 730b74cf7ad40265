#include <algorithm>

#include "deform/rigidity_rows.hpp"
#include "deform/rotation_clusters.hpp"
#include "deform/rotation_fit.hpp"

// RotationFrames' coarse rotation field (rotation_clusters.hpp,
// docs/method.md): its set-up over the rows' patches, and its part of the
// local step, the clusters' fits and their shares of the right-hand side.
namespace dfm::deform {

namespace {

constexpr std::size_t slots = RigidityStencil::slots;

// Clusters of the coarse rotation field per ROI. Fewer carry a change of pose
// across the ROI in fewer iterations and resist folds more; more follow
// bends and twists more closely (docs/method.md).
constexpr std::size_t clusters_per_roi = 16;

// Patches of rows per ROI that share one blend of the clusters' rotations:
// enough that the blend changes smoothly, few enough that the clusters'
// work is small beside the rows'.
constexpr std::size_t patches_per_roi = 512;

// How far ahead the patch sums fetch a row's stencil.
constexpr std::size_t prefetch_rows = 4;

}  // namespace

RotationClusters coarse_clusters(const MeshModel& model, const SystemRows& rows) {
    const std::size_t dual_rows = rows.size();
    std::vector<std::uint32_t> row_of(model.mesh.face_count(), mesh::no_index);
    for (std::size_t r = 0; r < dual_rows; ++r)
        row_of[rows.faces[r]] = static_cast<std::uint32_t>(r);
    std::vector<std::array<std::uint32_t, 3>> ring(dual_rows);
    for (std::size_t r = 0; r < dual_rows; ++r) {
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t j = model.dual.neighbors[rows.faces[r]][k];
            ring[r][k] = j == mesh::no_index ? mesh::no_index : row_of[j];
        }
    }
    RotationClusters clusters;
    clusters.build(ring, clusters_per_roi, patches_per_roi);
    return clusters;
}

void RotationFrames::build_coarse_field(const RotationClusters& clusters) {
    const std::size_t dual_rows = stencils_.size();

    // A patch's rows are linear in their vertices as a row's are:
    // Σ_{f ∈ patch} A_f p = Σ_v p_v H_pvᵀ with H_pv = Σ_{f ∈ patch} G_f,slot(v),
    // so the patch's covariance is Σ_v p_v H_pvᵀ and its rows' share of Aᵀ t
    // at v, turned by R, is R H_pv. Summed here once, each H_pv over the
    // rows in order; each patch's vertices ascending.
    const std::size_t patches = clusters.patch_count();
    heaviest_.assign(dual_rows, mesh::no_index);
    std::vector<std::uint32_t> patch_rows(patches + 1, 0);
    for (std::size_t r = 0; r < dual_rows; ++r) ++patch_rows[clusters.patch_of(r) + 1];
    for (std::size_t p = 0; p < patches; ++p) patch_rows[p + 1] += patch_rows[p];
    std::vector<std::uint32_t> rows_by_patch(dual_rows);
    {
        std::vector<std::uint32_t> fill(patch_rows.begin(), patch_rows.end() - 1);
        for (std::size_t r = 0; r < dual_rows; ++r)
            rows_by_patch[fill[clusters.patch_of(r)]++] = static_cast<std::uint32_t>(r);
    }
    patch_offsets_.assign(1, 0);
    patch_pulls_.clear();
    member_offsets_.assign(1, 0);
    members_.clear();
    std::vector<std::uint32_t> pull_of(local_.size(), mesh::no_index);
    for (std::size_t p = 0; p < patches; ++p) {
        std::uint32_t heaviest = mesh::no_index;
        double heaviest_weight = 0.0;
        for (const RotationClusters::Membership& m : clusters.of(p)) {
            members_.push_back({m.cluster, coarse_share * m.weight});
            if (m.weight > heaviest_weight) {
                heaviest_weight = m.weight;
                heaviest = m.cluster;
            }
        }
        member_offsets_.push_back(static_cast<std::uint32_t>(members_.size()));
        const std::size_t first = patch_pulls_.size();
        for (std::uint32_t k = patch_rows[p]; k < patch_rows[p + 1]; ++k) {
            // A patch's rows lie apart in the stencils: the row a few
            // ahead is fetched while this one is summed.
            if (k + prefetch_rows < dual_rows) {
                const auto* ahead =
                    reinterpret_cast<const char*>(&stencils_[rows_by_patch[k + prefetch_rows]]);
                for (std::size_t byte = 0; byte < sizeof(RigidityStencil); byte += 64)
                    __builtin_prefetch(ahead + byte);
            }
            const std::uint32_t r = rows_by_patch[k];
            heaviest_[r] = heaviest;
            const RigidityStencil& st = stencils_[r];
            for (std::size_t i = 0; i < slots; ++i) {
                const glm::dvec3 g(st.g[0][i], st.g[1][i], st.g[2][i]);
                if (g == glm::dvec3(0.0)) continue;  // an unused slot
                const std::uint32_t v = st.vertex[i];
                if (pull_of[v] == mesh::no_index) {
                    pull_of[v] = static_cast<std::uint32_t>(patch_pulls_.size());
                    patch_pulls_.push_back({v, glm::dvec3(0.0)});
                }
                patch_pulls_[pull_of[v]].pulled += g;
            }
        }
        std::sort(patch_pulls_.begin() + static_cast<std::ptrdiff_t>(first), patch_pulls_.end(),
                  [](const PatchPull& x, const PatchPull& y) { return x.vertex < y.vertex; });
        for (std::size_t k = first; k < patch_pulls_.size(); ++k)
            pull_of[patch_pulls_[k].vertex] = mesh::no_index;
        patch_offsets_.push_back(static_cast<std::uint32_t>(patch_pulls_.size()));
    }
    cluster_kept_.assign(clusters.size(), glm::dquat(1.0, 0.0, 0.0, 0.0));
    cluster_fitted_ = cluster_kept_;
    cluster_rotations_.assign(clusters.size(), glm::dmat3(1.0));
    cluster_sums_.assign(clusters.size(), glm::dmat3(0.0));
}

// Each cluster's rotation fitted to its patches' covariances, weighted (a
// patch's taken from its first vertex's position: Σ_v H_pv = 0, and the sum
// cancels less).
double RotationFrames::fit_clusters(int steps) {
    const std::span<const glm::dvec3> positions = local_;
    std::vector<glm::dmat3>& sums = cluster_sums_;
    std::fill(sums.begin(), sums.end(), glm::dmat3(0.0));
    for (std::size_t p = 0; p + 1 < patch_offsets_.size(); ++p) {
        const std::span<const PatchPull> pulls = patch_pulls(p);
        glm::dmat3 covariance(0.0);
        const glm::dvec3 origin = pulls.empty() ? glm::dvec3(0.0) : positions[pulls[0].vertex];
        for (const PatchPull& t : pulls)
            covariance += glm::outerProduct(positions[t.vertex] - origin, t.pulled);
        for (const Member& m : patch_members(p)) sums[m.cluster] += m.share * covariance;
    }
    double cluster_alignment = 0.0;
    for (std::size_t c = 0; c < cluster_kept_.size(); ++c) {
        glm::dquat q = cluster_kept_[c];
        const RotationFit fit = fit_rotation(sums[c], q, steps);
        cluster_fitted_[c] = q;
        cluster_rotations_[c] = fit.rotation;
        cluster_alignment += fit.alignment;
    }
    return cluster_alignment;
}

// The clusters' shares of Aᵀ t: θ Σ_c κ_pc R_c H_pv at each unknown.
void RotationFrames::add_cluster_shares(std::span<double> rhs) const {
    const std::size_t unknowns = rhs.size() / 3;
    for (std::size_t p = 0; p + 1 < patch_offsets_.size(); ++p) {
        const std::span<const Member> members = patch_members(p);
        if (members.empty()) continue;
        glm::dmat3 rotation(0.0);
        for (const Member& m : members) rotation += m.share * cluster_rotations_[m.cluster];
        for (const PatchPull& t : patch_pulls(p)) {
            if (t.vertex >= unknowns) continue;
            const glm::dvec3 share = rotation * t.pulled;
            double* out = &rhs[3 * t.vertex];
            out[0] += share.x;
            out[1] += share.y;
            out[2] += share.z;
        }
    }
}

}  // namespace dfm::deform
