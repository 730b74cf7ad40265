#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

// The default method's coarse rotation field (docs/method.md): the ROI's dual
// rows gathered around a few seeds, each cluster turned by one rotation
// fitted to the rows around it, and every row's coarse rotation a blend of
// the rotations of the clusters near it. A rotation shared by a whole region
// carries a change of pose across the ROI in one iteration, where a row's own
// rotation learns it from its neighbours one ring at a time; and a fold,
// whose rows turn over against their neighbours, cannot hide from it.
namespace dfm::deform {

class RotationClusters {
public:
    // A row's share of one cluster.
    struct Membership {
        std::uint32_t cluster;
        double weight;  // the weights of a row sum to 1
    };

    // Seeds `count` clusters (fewer if there are fewer rows) over the rows,
    // `ring[r]` holding the rows across row r's three edges (no_index for
    // none), and weighs each row's clusters by their distance in steps
    // between neighbouring rows. Deterministic: the same rows give the same
    // clusters.
    void build(std::span<const std::array<std::uint32_t, 3>> ring, std::size_t count);

    std::size_t size() const { return cluster_count_; }
    // The clusters of row r. Empty for a row that no seed reaches (a part
    // of the ROI beyond `count` separate parts): that row keeps its own
    // rotation alone.
    std::span<const Membership> of(std::size_t row) const {
        return std::span(members_).subspan(offsets_[row], offsets_[row + 1] - offsets_[row]);
    }

private:
    std::size_t cluster_count_ = 0;
    std::vector<std::uint32_t> offsets_;  // per row, into members_
    std::vector<Membership> members_;
};

}  // namespace dfm::deform
