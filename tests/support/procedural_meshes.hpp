#pragma once

#include <cstdint>

#include "mesh/mesh.hpp"

// Small meshes made in code, so unit tests need no files.
namespace dfm::test {

// A unit sphere: the icosahedron split `subdivisions` times, outward facing.
// 10 * 4^k + 2 vertices, 20 * 4^k faces.
mesh::Mesh make_icosphere(int subdivisions);

// A closed, capped cylinder along +y ("limb"): `segments` around, `rings`
// bands along its length, one centre vertex per cap, outward facing.
mesh::Mesh make_limb(int segments, int rings, double radius, double length);

// An open grid of nx by ny unit squares in the z = 0 plane, two triangles
// each, facing +z.
mesh::Mesh make_grid(int nx, int ny);

}  // namespace dfm::test
