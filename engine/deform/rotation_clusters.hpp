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
//
// The blend is the same over a patch of neighbouring rows, a few hundred
// patches to a ROI: the clusters' work then grows with the patches, not with
// the rows, and a patch's rows can be summed once (RotationFrames).
namespace dfm::deform {

class RotationClusters {
public:
    // A patch's share of one cluster.
    struct Membership {
        std::uint32_t cluster;
        double weight;  // the weights of a patch sum to 1
    };

    // Gathers the rows in about `patches` patches of neighbouring rows
    // (each row its own where there are fewer), seeds `clusters` clusters
    // (fewer if there are fewer patches) over the patches, and weighs each
    // patch's clusters by their distance in steps between neighbouring
    // patches. `ring[r]` holds the rows across row r's three edges (no_index
    // for none). Deterministic: the same rows give the same clusters.
    void build(std::span<const std::array<std::uint32_t, 3>> ring, std::size_t clusters,
               std::size_t patches);

    // Renumbers the rows: new row r is old row old_row_of[r], every old row
    // listed once. The patches and clusters stay.
    void reorder_rows(std::span<const std::uint32_t> old_row_of);

    std::size_t size() const { return cluster_count_; }
    std::size_t patch_count() const { return offsets_.size() - 1; }
    std::uint32_t patch_of(std::size_t row) const { return patch_of_[row]; }
    // The clusters of patch p. Empty for a patch that no seed reaches (a
    // part of the ROI beyond as many separate parts as there are clusters):
    // its rows keep their own rotations alone.
    std::span<const Membership> of(std::size_t patch) const {
        return std::span(members_).subspan(offsets_[patch], offsets_[patch + 1] - offsets_[patch]);
    }

private:
    std::size_t cluster_count_ = 0;
    std::vector<std::uint32_t> patch_of_;       // per row
    std::vector<std::uint32_t> offsets_ = {0};  // per patch, into members_
    std::vector<Membership> members_;
};

}  // namespace dfm::deform
