#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "core/memory_bytes.hpp"
#include "core/pooled_allocator.hpp"

namespace dfm::solver {

// A sparse matrix in compressed sparse row form: the entries of row i are
// col_indices/values[row_offsets[i] .. row_offsets[i + 1]), columns
// ascending, no duplicates.
struct CsrMatrix {
    std::size_t rows = 0;
    std::size_t cols = 0;
    PooledVector<std::size_t> row_offsets;
    PooledVector<std::uint32_t> col_indices;
    PooledVector<double> values;

    std::size_t memory_bytes() const { return capacity_bytes(row_offsets, col_indices, values); }

    // The stored entries; counted by their columns, so that a pattern
    // alone (values left empty) has them too.
    std::size_t nonzeros() const { return col_indices.size(); }

    // y = A x for `k` interleaved vectors: x[j * k + c] is entry j of vector
    // c. One pass over the matrix serves all k.
    void multiply(std::span<const double> x, std::span<double> y, std::size_t k = 1) const;

    // The diagonal entries (0 where a row stores none).
    std::vector<double> diagonal() const;
};

struct Triplet {
    std::uint32_t row;
    std::uint32_t col;
    double value;
};

// Builds a CSR matrix from triplets, summing duplicates. Sorts `triplets`.
CsrMatrix csr_from_triplets(std::size_t rows, std::size_t cols, std::vector<Triplet>& triplets);

}  // namespace dfm::solver
