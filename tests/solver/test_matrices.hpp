#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "mesh/mesh.hpp"
#include "solver/csr_matrix.hpp"

// Matrices and reference solutions for the solver tests.
namespace dfm::test {

// A deterministic generator, the same on every platform.
class Random {
public:
    explicit Random(std::uint64_t seed) : state_(seed) {}
    std::uint64_t next();
    double uniform(double low, double high);  // [low, high)
    std::size_t below(std::size_t n);

private:
    std::uint64_t state_;
};

// A random symmetric positive definite n×n matrix with about `per_row`
// off-diagonal entries a row, strictly diagonally dominant.
solver::CsrMatrix random_spd(std::size_t n, std::size_t per_row, std::uint64_t seed);

// A random non-symmetric n×n matrix (pattern included), diagonally dominant.
solver::CsrMatrix random_nonsymmetric(std::size_t n, std::size_t per_row, std::uint64_t seed);

// A hub joined to every other vertex plus a path through the others;
// diagonally dominant.
solver::CsrMatrix star_matrix(std::size_t n);

// Every vertex joined to every other; diagonally dominant.
solver::CsrMatrix complete_matrix(std::size_t n);

// The 5-point Laplacian of an nx×ny grid with Dirichlet boundary (SPD).
solver::CsrMatrix grid_laplacian(std::size_t nx, std::size_t ny);

// Lᵀ L (+ shift I) for a sparse L: the bi-Laplacian when L is a Laplacian.
solver::CsrMatrix normal_product(const solver::CsrMatrix& l, double shift);

// The uniform graph Laplacian of a mesh's vertex graph plus `shift` on the
// diagonal (SPD for shift > 0).
solver::CsrMatrix mesh_laplacian(const mesh::Mesh& mesh, double shift);

std::vector<double> to_dense(const solver::CsrMatrix& a);

// x = A⁻¹ b for k interleaved columns, by Gaussian elimination with partial
// pivoting on the dense matrix.
std::vector<double> dense_solve(const solver::CsrMatrix& a, const std::vector<double>& b,
                                std::size_t k);

// ‖b − A x‖₂ / ‖b‖₂ over all k columns together.
double relative_residual(const solver::CsrMatrix& a, const std::vector<double>& x,
                         const std::vector<double>& b, std::size_t k);

// max |x − y| / max |y|.
double relative_difference(const std::vector<double>& x, const std::vector<double>& y);

std::vector<double> random_vector(std::size_t size, std::uint64_t seed);

}  // namespace dfm::test
