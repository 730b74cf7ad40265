#pragma once

#include <cstdint>
#include <span>

#include "deform/normal_system.hpp"
#include "deform/rotation_clusters.hpp"

// The default method's rows and unknowns in the surface's order. Its local
// step reads each dual row's vertices and adds to their unknowns' share of
// the right-hand side, row after row. In the host's order (a scan's, or a
// subdivision's, which numbers each edge's new vertex apart from the
// corners) neighbouring rows and their vertices lie anywhere in memory, and
// nearly every read misses the cache. Listed patch by patch of the coarse
// field (rotation_clusters.hpp), a few hundred neighbouring rows each, and
// with the unknowns numbered in the order those rows first name them, the
// step walks memory in step with the surface. Only the order changes: the
// same rows, clusters and unknowns, so the same result up to the rounding
// of sums taken in another order.
namespace dfm::deform {

// Lists `rows` patch by patch of `clusters` (each patch's rows in their
// order) and renumbers the unknowns in the order those rows name them (an
// unknown no row names keeps its place after them): the rows' entries,
// `unknowns` and the unknowns in `soft_handles` follow, and so does
// `clusters`, which was made over the rows as they were.
void order_by_patch(RotationClusters& clusters, SystemRows& rows, UnknownMap& unknowns,
                    std::span<std::uint32_t> soft_handles);

}  // namespace dfm::deform
