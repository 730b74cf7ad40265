#include "solver/csr_matrix.hpp"

#include <algorithm>

namespace dfm::solver {

void CsrMatrix::multiply(std::span<const double> x, std::span<double> y, std::size_t k) const {
    for (std::size_t i = 0; i < rows; ++i) {
        double* yi = &y[i * k];
        for (std::size_t c = 0; c < k; ++c) yi[c] = 0.0;
        for (std::size_t p = row_offsets[i]; p < row_offsets[i + 1]; ++p) {
            const double a = values[p];
            const double* xj = &x[col_indices[p] * k];
            for (std::size_t c = 0; c < k; ++c) yi[c] += a * xj[c];
        }
    }
}

std::vector<double> CsrMatrix::diagonal() const {
    std::vector<double> d(std::min(rows, cols), 0.0);
    for (std::size_t i = 0; i < d.size(); ++i) {
        const auto begin = col_indices.begin() + static_cast<std::ptrdiff_t>(row_offsets[i]);
        const auto end = col_indices.begin() + static_cast<std::ptrdiff_t>(row_offsets[i + 1]);
        const auto it = std::lower_bound(begin, end, static_cast<std::uint32_t>(i));
        if (it != end && *it == i)
            d[i] = values[static_cast<std::size_t>(it - col_indices.begin())];
    }
    return d;
}

CsrMatrix csr_from_triplets(std::size_t rows, std::size_t cols, std::vector<Triplet>& triplets) {
    std::sort(triplets.begin(), triplets.end(), [](const Triplet& a, const Triplet& b) {
        return a.row != b.row ? a.row < b.row : a.col < b.col;
    });
    CsrMatrix m;
    m.rows = rows;
    m.cols = cols;
    m.row_offsets.assign(rows + 1, 0);
    for (std::size_t t = 0; t < triplets.size();) {
        std::size_t u = t;
        double sum = 0.0;
        while (u < triplets.size() && triplets[u].row == triplets[t].row &&
               triplets[u].col == triplets[t].col) {
            sum += triplets[u].value;
            ++u;
        }
        m.col_indices.push_back(triplets[t].col);
        m.values.push_back(sum);
        ++m.row_offsets[triplets[t].row + 1];
        t = u;
    }
    for (std::size_t i = 0; i < rows; ++i) m.row_offsets[i + 1] += m.row_offsets[i];
    return m;
}

}  // namespace dfm::solver
