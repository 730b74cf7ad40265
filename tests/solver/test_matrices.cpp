#include "solver/test_matrices.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

#include "mesh/adjacency.hpp"

namespace dfm::test {

using solver::CsrMatrix;
using solver::Triplet;

std::uint64_t Random::next() {
    std::uint64_t z = (state_ += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
}

double Random::uniform(double low, double high) {
    return low + (high - low) * static_cast<double>(next() >> 11) * 0x1.0p-53;
}

std::size_t Random::below(std::size_t n) {
    return static_cast<std::size_t>(next() % n);
}

namespace {

// Off-diagonal entries at random places; the diagonal then exceeds the sum
// of each row's (and column's) magnitudes.
CsrMatrix random_dominant(std::size_t n, std::size_t per_row, std::uint64_t seed, bool symmetric) {
    Random random(seed);
    std::vector<Triplet> triplets;
    std::vector<double> row_sum(n, 0.0);
    std::vector<double> col_sum(n, 0.0);
    for (std::size_t i = 0; i < n; ++i) {
        for (std::size_t t = 0; t < per_row / (symmetric ? 2 : 1); ++t) {
            const std::size_t j = random.below(n);
            if (j == i) continue;
            const double v = random.uniform(-1.0, 1.0);
            const auto r = static_cast<std::uint32_t>(i);
            const auto c = static_cast<std::uint32_t>(j);
            triplets.push_back({r, c, v});
            row_sum[i] += std::abs(v);
            col_sum[j] += std::abs(v);
            if (symmetric) {
                triplets.push_back({c, r, v});
                row_sum[j] += std::abs(v);
                col_sum[i] += std::abs(v);
            }
        }
    }
    for (std::size_t i = 0; i < n; ++i) {
        const auto r = static_cast<std::uint32_t>(i);
        triplets.push_back({r, r, std::max(row_sum[i], col_sum[i]) + random.uniform(0.5, 1.5)});
    }
    return solver::csr_from_triplets(n, n, triplets);
}

}  // namespace

CsrMatrix random_spd(std::size_t n, std::size_t per_row, std::uint64_t seed) {
    return random_dominant(n, per_row, seed, true);
}

CsrMatrix random_nonsymmetric(std::size_t n, std::size_t per_row, std::uint64_t seed) {
    return random_dominant(n, per_row, seed, false);
}

CsrMatrix star_matrix(std::size_t n) {
    std::vector<Triplet> triplets;
    for (std::uint32_t i = 0; i < n; ++i) {
        triplets.push_back({i, i, static_cast<double>(n)});
        if (i > 0) {
            triplets.push_back({0, i, -1.0});
            triplets.push_back({i, 0, -1.0});
        }
        if (i > 1) {
            triplets.push_back({i - 1, i, -0.5});
            triplets.push_back({i, i - 1, -0.5});
        }
    }
    return csr_from_triplets(n, n, triplets);
}

CsrMatrix complete_matrix(std::size_t n) {
    std::vector<Triplet> triplets;
    for (std::uint32_t i = 0; i < n; ++i)
        for (std::uint32_t j = 0; j < n; ++j)
            triplets.push_back({i, j, i == j ? static_cast<double>(n) : -0.5});
    return csr_from_triplets(n, n, triplets);
}

CsrMatrix grid_laplacian(std::size_t nx, std::size_t ny) {
    std::vector<Triplet> triplets;
    const auto at = [&](std::size_t x, std::size_t y) {
        return static_cast<std::uint32_t>(y * nx + x);
    };
    for (std::size_t y = 0; y < ny; ++y) {
        for (std::size_t x = 0; x < nx; ++x) {
            triplets.push_back({at(x, y), at(x, y), 4.0});
            if (x > 0) triplets.push_back({at(x, y), at(x - 1, y), -1.0});
            if (x + 1 < nx) triplets.push_back({at(x, y), at(x + 1, y), -1.0});
            if (y > 0) triplets.push_back({at(x, y), at(x, y - 1), -1.0});
            if (y + 1 < ny) triplets.push_back({at(x, y), at(x, y + 1), -1.0});
        }
    }
    return solver::csr_from_triplets(nx * ny, nx * ny, triplets);
}

CsrMatrix normal_product(const CsrMatrix& l, double shift) {
    // LᵀL is the sum over the rows of L of each row's outer product.
    std::vector<Triplet> triplets;
    for (std::size_t i = 0; i < l.rows; ++i)
        for (std::size_t p = l.row_offsets[i]; p < l.row_offsets[i + 1]; ++p)
            for (std::size_t q = l.row_offsets[i]; q < l.row_offsets[i + 1]; ++q)
                triplets.push_back({l.col_indices[p], l.col_indices[q], l.values[p] * l.values[q]});
    for (std::size_t j = 0; j < l.cols; ++j) {
        const auto c = static_cast<std::uint32_t>(j);
        triplets.push_back({c, c, shift});
    }
    return solver::csr_from_triplets(l.cols, l.cols, triplets);
}

CsrMatrix mesh_laplacian(const mesh::Mesh& mesh, double shift) {
    const mesh::VertexAdjacency adjacency = mesh::build_vertex_adjacency(mesh);
    std::vector<Triplet> triplets;
    for (std::uint32_t v = 0; v < mesh.vertex_count(); ++v) {
        const auto neighbors = adjacency.of(v);
        triplets.push_back({v, v, static_cast<double>(neighbors.size()) + shift});
        for (const std::uint32_t u : neighbors) triplets.push_back({v, u, -1.0});
    }
    return solver::csr_from_triplets(mesh.vertex_count(), mesh.vertex_count(), triplets);
}

std::vector<double> to_dense(const CsrMatrix& a) {
    std::vector<double> d(a.rows * a.cols, 0.0);
    for (std::size_t i = 0; i < a.rows; ++i)
        for (std::size_t p = a.row_offsets[i]; p < a.row_offsets[i + 1]; ++p)
            d[i * a.cols + a.col_indices[p]] = a.values[p];
    return d;
}

std::vector<double> dense_solve(const CsrMatrix& a, const std::vector<double>& b, std::size_t k) {
    const std::size_t n = a.rows;
    std::vector<double> m = to_dense(a);
    std::vector<double> x = b;
    for (std::size_t col = 0; col < n; ++col) {
        std::size_t pivot = col;
        for (std::size_t r = col + 1; r < n; ++r)
            if (std::abs(m[r * n + col]) > std::abs(m[pivot * n + col])) pivot = r;
        if (pivot != col) {
            for (std::size_t j = 0; j < n; ++j) std::swap(m[col * n + j], m[pivot * n + j]);
            for (std::size_t c = 0; c < k; ++c) std::swap(x[col * k + c], x[pivot * k + c]);
        }
        for (std::size_t r = col + 1; r < n; ++r) {
            const double f = m[r * n + col] / m[col * n + col];
            if (f == 0.0) continue;
            for (std::size_t j = col; j < n; ++j) m[r * n + j] -= f * m[col * n + j];
            for (std::size_t c = 0; c < k; ++c) x[r * k + c] -= f * x[col * k + c];
        }
    }
    for (std::size_t col = n; col-- > 0;) {
        for (std::size_t c = 0; c < k; ++c) {
            double v = x[col * k + c];
            for (std::size_t j = col + 1; j < n; ++j) v -= m[col * n + j] * x[j * k + c];
            x[col * k + c] = v / m[col * n + col];
        }
    }
    return x;
}

double relative_residual(const CsrMatrix& a, const std::vector<double>& x,
                         const std::vector<double>& b, std::size_t k) {
    std::vector<double> ax(b.size());
    a.multiply(x, ax, k);
    double r2 = 0.0;
    double b2 = 0.0;
    for (std::size_t i = 0; i < b.size(); ++i) {
        r2 += (b[i] - ax[i]) * (b[i] - ax[i]);
        b2 += b[i] * b[i];
    }
    return std::sqrt(r2 / b2);
}

double relative_difference(const std::vector<double>& x, const std::vector<double>& y) {
    double diff = 0.0;
    double scale = 0.0;
    for (std::size_t i = 0; i < y.size(); ++i) {
        diff = std::max(diff, std::abs(x[i] - y[i]));
        scale = std::max(scale, std::abs(y[i]));
    }
    return diff / scale;
}

std::vector<double> random_vector(std::size_t size, std::uint64_t seed) {
    Random random(seed);
    std::vector<double> v(size);
    for (double& x : v) x = random.uniform(-1.0, 1.0);
    return v;
}

}  // namespace dfm::test
