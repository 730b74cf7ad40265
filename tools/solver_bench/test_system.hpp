#pragma once

#include <cstddef>
#include <vector>

#include "mesh/mesh.hpp"
#include "solver/csr_matrix.hpp"

// A stand-in for an edit's normal matrix with the same sparsity (vertex
// 2-rings) and conditioning: N = LᵀL + w² H + ε I, L the mesh's uniform
// graph Laplacian, H marking the handle and fixed vertices.
namespace dfm::solver_bench {

struct TestSystem {
    solver::CsrMatrix matrix;
    std::vector<double> handle_weight;  // w² on the diagonal of H, per vertex
    std::vector<std::size_t> moving;    // the vertices of the dragged handle
    double diagonal = 0.0;              // the mesh's bounding-box diagonal
};

// Every triangle split into four at its edges' midpoints.
mesh::Mesh subdivide_midpoint(const mesh::Mesh& mesh);

// Fixed vertices: the lowest 5% along y; the dragged handle: the highest 5%.
TestSystem make_test_system(const mesh::Mesh& mesh);

}  // namespace dfm::solver_bench
