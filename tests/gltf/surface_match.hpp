#pragma once

#include <cstdint>
#include <vector>

// Which vertex of a welded surface each vertex of its seam-split copy is,
// found from the files alone (apart from the SDK's weld): by exact position,
// and where two surface vertices share a position (the cow has such a
// pair), by the triangles around it.
namespace dfm::test::gltf {

// Points and triangles as flat arrays: x0, y0, z0, x1, ... and a0, b0, c0, ...
struct Surface {
    std::vector<double> positions;
    std::vector<std::uint32_t> triangles;
};

// For each vertex of `split`, its vertex of `welded`; fails the test when a
// vertex has no position in `welded` or its triangles leave it ambiguous.
std::vector<std::uint32_t> match_surface(const Surface& split, const Surface& welded);

// The lowest-numbered vertex of `positions` at exactly `p`; fails the test
// when there is none.
std::uint32_t vertex_at(const std::vector<double>& positions, const double p[3]);

}  // namespace dfm::test::gltf
