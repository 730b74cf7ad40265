#include "deform/rotation_clusters.hpp"

#include <algorithm>
#include <limits>

#include "mesh/mesh.hpp"

namespace dfm::deform {

namespace {

constexpr std::uint32_t unreached = std::numeric_limits<std::uint32_t>::max();

// A cluster reaches the patches within twice the seeds' covering radius:
// every patch lies within one radius of a seed, so it blends that cluster
// and the few beyond it, and its blend changes a little from one patch to
// the next.
constexpr std::uint32_t reach_factor = 2;

// The patches' neighbours, CSR.
struct PatchGraph {
    std::vector<std::uint32_t> offsets;
    std::vector<std::uint32_t> neighbors;

    std::span<const std::uint32_t> of(std::uint32_t p) const {
        return std::span(neighbors).subspan(offsets[p], offsets[p + 1] - offsets[p]);
    }
};

// Steps from `from` to the patches it brings closer than `distance` says
// (all of them when `distance` is fresh), below `limit`; the patches reached
// are appended to `reached` in the order met.
void spread(const PatchGraph& graph, std::uint32_t from, std::uint32_t limit,
            std::vector<std::uint32_t>& distance, std::vector<std::uint32_t>& reached) {
    const std::size_t first = reached.size();
    distance[from] = 0;
    reached.push_back(from);
    for (std::size_t head = first; head < reached.size(); ++head) {
        const std::uint32_t p = reached[head];
        const std::uint32_t step = distance[p] + 1;
        if (step >= limit) continue;
        for (const std::uint32_t q : graph.of(p)) {
            if (distance[q] <= step) continue;
            distance[q] = step;
            reached.push_back(q);
        }
    }
}

}  // namespace

void RotationClusters::build(std::span<const std::array<std::uint32_t, 3>> ring,
                             std::size_t clusters, std::size_t patches) {
    const std::size_t rows = ring.size();
    cluster_count_ = 0;
    patch_of_.assign(rows, unreached);
    offsets_.assign(1, 0);
    members_.clear();
    if (rows == 0 || clusters == 0) return;

    // Patches grown breadth-first, each from the lowest row not yet taken,
    // to `size` rows (fewer where its neighbours are taken).
    const std::size_t size = std::max<std::size_t>(1, rows / std::max<std::size_t>(patches, 1));
    std::uint32_t count = 0;
    std::vector<std::uint32_t> grown;
    for (std::uint32_t start = 0; start < rows; ++start) {
        if (patch_of_[start] != unreached) continue;
        grown.assign(1, start);
        patch_of_[start] = count;
        for (std::size_t head = 0; head < grown.size() && grown.size() < size; ++head) {
            for (const std::uint32_t j : ring[grown[head]]) {
                if (j == mesh::no_index || patch_of_[j] != unreached || grown.size() == size)
                    continue;
                patch_of_[j] = count;
                grown.push_back(j);
            }
        }
        ++count;
    }
    PatchGraph graph;
    {
        std::vector<std::array<std::uint32_t, 2>> pairs;
        for (std::size_t r = 0; r < rows; ++r) {
            for (const std::uint32_t j : ring[r]) {
                if (j != mesh::no_index && patch_of_[j] != patch_of_[r])
                    pairs.push_back({patch_of_[r], patch_of_[j]});
            }
        }
        std::sort(pairs.begin(), pairs.end());
        pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
        graph.offsets.assign(count + 1, 0);
        for (const auto& pair : pairs) ++graph.offsets[pair[0] + 1];
        for (std::uint32_t p = 0; p < count; ++p) graph.offsets[p + 1] += graph.offsets[p];
        for (const auto& pair : pairs) graph.neighbors.push_back(pair[1]);
    }

    // Farthest-point seeds: each next seed is the patch farthest from the
    // seeds so far (a patch no seed reaches first, then the lowest index on
    // a tie), so the seeds cover the patches evenly.
    std::vector<std::uint32_t> distance(count, unreached);
    std::vector<std::uint32_t> seeds;
    std::vector<std::uint32_t> reached;
    std::uint32_t next = 0;
    while (seeds.size() < clusters) {
        seeds.push_back(next);
        reached.clear();
        spread(graph, next, unreached, distance, reached);
        const auto farthest = std::max_element(distance.begin(), distance.end());
        if (*farthest == 0) break;  // every patch is a seed
        next = static_cast<std::uint32_t>(farthest - distance.begin());
    }
    std::uint32_t radius = 1;
    for (const std::uint32_t d : distance) {
        if (d != unreached) radius = std::max(radius, d);
    }
    const std::uint32_t reach = reach_factor * radius;

    // Each cluster's patches within reach, weighed by a bump that falls
    // smoothly to zero there; the memberships gathered by patch, in cluster
    // order.
    struct Entry {
        std::uint32_t patch;
        Membership membership;
    };
    std::vector<Entry> entries;
    std::vector<std::uint32_t> local(count, unreached);
    for (std::uint32_t c = 0; c < seeds.size(); ++c) {
        reached.clear();
        spread(graph, seeds[c], reach, local, reached);
        for (const std::uint32_t p : reached) {
            const double x = static_cast<double>(local[p]) / reach;
            entries.push_back({p, {c, (1.0 - x * x) * (1.0 - x * x)}});
            local[p] = unreached;
        }
    }
    offsets_.assign(count + 1, 0);
    for (const Entry& e : entries) ++offsets_[e.patch + 1];
    for (std::uint32_t p = 0; p < count; ++p) offsets_[p + 1] += offsets_[p];
    members_.resize(entries.size());
    std::vector<std::uint32_t> fill(offsets_.begin(), offsets_.end() - 1);
    for (const Entry& e : entries) members_[fill[e.patch]++] = e.membership;
    for (std::uint32_t p = 0; p < count; ++p) {
        double total = 0.0;
        for (std::uint32_t k = offsets_[p]; k < offsets_[p + 1]; ++k) total += members_[k].weight;
        for (std::uint32_t k = offsets_[p]; k < offsets_[p + 1]; ++k) members_[k].weight /= total;
    }
    cluster_count_ = seeds.size();
}

void RotationClusters::reorder_rows(std::span<const std::uint32_t> old_row_of) {
    std::vector<std::uint32_t> patch_of(old_row_of.size());
    for (std::size_t r = 0; r < old_row_of.size(); ++r) patch_of[r] = patch_of_[old_row_of[r]];
    patch_of_ = std::move(patch_of);
}

}  // namespace dfm::deform
