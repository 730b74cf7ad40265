#include "deform/rotation_clusters.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "mesh/mesh.hpp"

namespace dfm::deform {

namespace {

constexpr std::uint32_t unreached = std::numeric_limits<std::uint32_t>::max();

// A cluster reaches the rows within twice the seeds' covering radius: every
// row lies within one radius of a seed, so it blends that cluster and the
// few beyond it, and its blend changes a little from one row to the next.
constexpr double reach_factor = 2.0;

// Steps from `from` to the rows it brings closer than `distance` says (all of
// them when `distance` is fresh), below `limit`; the rows reached are
// appended to `reached` in the order met.
void spread(std::span<const std::array<std::uint32_t, 3>> ring, std::uint32_t from,
            std::uint32_t limit, std::vector<std::uint32_t>& distance,
            std::vector<std::uint32_t>& reached) {
    const std::size_t first = reached.size();
    distance[from] = 0;
    reached.push_back(from);
    for (std::size_t head = first; head < reached.size(); ++head) {
        const std::uint32_t r = reached[head];
        const std::uint32_t step = distance[r] + 1;
        if (step >= limit) continue;
        for (const std::uint32_t j : ring[r]) {
            if (j == mesh::no_index || distance[j] <= step) continue;
            distance[j] = step;
            reached.push_back(j);
        }
    }
}

}  // namespace

void RotationClusters::build(std::span<const std::array<std::uint32_t, 3>> ring,
                             std::size_t count) {
    const std::size_t rows = ring.size();
    cluster_count_ = 0;
    offsets_.assign(rows + 1, 0);
    members_.clear();
    if (rows == 0 || count == 0) return;

    // Farthest-point seeds: each next seed is the row farthest from the seeds
    // so far (a row no seed reaches first, then the lowest index on a tie),
    // so the seeds cover the rows evenly.
    std::vector<std::uint32_t> distance(rows, unreached);
    std::vector<std::uint32_t> seeds;
    std::vector<std::uint32_t> reached;
    reached.reserve(rows);
    std::uint32_t next = 0;
    while (seeds.size() < count) {
        seeds.push_back(next);
        reached.clear();
        spread(ring, next, unreached, distance, reached);
        const auto farthest = std::max_element(distance.begin(), distance.end());
        if (*farthest == 0) break;  // every row is a seed
        next = static_cast<std::uint32_t>(farthest - distance.begin());
    }
    std::uint32_t radius = 1;
    for (const std::uint32_t d : distance) {
        if (d != unreached) radius = std::max(radius, d);
    }
    const auto reach = static_cast<std::uint32_t>(std::ceil(reach_factor * radius));

    // Each cluster's rows within reach, weighed by a bump that falls
    // smoothly to zero there; the memberships gathered by row, in cluster
    // order.
    struct Entry {
        std::uint32_t row;
        Membership membership;
    };
    std::vector<Entry> entries;
    std::vector<std::uint32_t> local(rows, unreached);
    for (std::uint32_t c = 0; c < seeds.size(); ++c) {
        reached.clear();
        spread(ring, seeds[c], reach, local, reached);
        for (const std::uint32_t r : reached) {
            const double x = static_cast<double>(local[r]) / reach;
            entries.push_back({r, {c, (1.0 - x * x) * (1.0 - x * x)}});
            local[r] = unreached;
        }
    }
    for (const Entry& e : entries) ++offsets_[e.row + 1];
    for (std::size_t r = 0; r < rows; ++r) offsets_[r + 1] += offsets_[r];
    members_.resize(entries.size());
    std::vector<std::uint32_t> fill(offsets_.begin(), offsets_.end() - 1);
    for (const Entry& e : entries) members_[fill[e.row]++] = e.membership;
    for (std::size_t r = 0; r < rows; ++r) {
        double total = 0.0;
        for (std::uint32_t k = offsets_[r]; k < offsets_[r + 1]; ++k) total += members_[k].weight;
        for (std::uint32_t k = offsets_[r]; k < offsets_[r + 1]; ++k) members_[k].weight /= total;
    }
    cluster_count_ = seeds.size();
}

}  // namespace dfm::deform
