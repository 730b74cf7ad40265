#include <cmath>
#include <limits>
#include <string>

#include "solver/preconditioner.hpp"

namespace dfm::solver {

namespace {

constexpr std::size_t no_entry = std::numeric_limits<std::size_t>::max();
// Shifts tried after a breakdown: α = first_shift · shift_growth^t.
constexpr double first_shift = 1e-3;
constexpr double shift_growth = 4.0;
constexpr int shift_attempts = 12;

// The lower triangle of A, diagonal last in each row; fails on a row whose
// diagonal is missing or not positive.
Status lower_triangle(const CsrMatrix& a, CsrMatrix& lower) {
    lower = CsrMatrix{};
    lower.rows = lower.cols = a.rows;
    lower.row_offsets.assign(1, 0);
    for (std::size_t i = 0; i < a.rows; ++i) {
        for (std::size_t p = a.row_offsets[i]; p < a.row_offsets[i + 1]; ++p) {
            if (a.col_indices[p] > i) break;
            lower.col_indices.push_back(a.col_indices[p]);
            lower.values.push_back(a.values[p]);
        }
        if (lower.col_indices.size() == lower.row_offsets.back() || lower.col_indices.back() != i ||
            !(lower.values.back() > 0.0) || !std::isfinite(lower.values.back()))
            return {Errc::numerical, "incomplete Cholesky: row " + std::to_string(i) +
                                         " has no positive diagonal entry"};
        lower.row_offsets.push_back(lower.col_indices.size());
    }
    return Status::ok();
}

// IC(0) in place on `l` (A's lower triangle, its diagonal scaled by
// 1 + shift), row by row: L(i, k) = (A(i, k) − Σ_j L(i, j) L(k, j)) / L(k, k)
// over the j both rows hold. Returns the first row whose pivot is not
// positive, or no_entry.
std::size_t factor_in_place(CsrMatrix& l, double shift, std::vector<std::size_t>& where) {
    const std::size_t n = l.rows;
    for (std::size_t i = 0; i < n; ++i) {
        const std::size_t begin = l.row_offsets[i];
        const std::size_t diagonal = l.row_offsets[i + 1] - 1;
        for (std::size_t p = begin; p < diagonal; ++p) where[l.col_indices[p]] = p;
        for (std::size_t p = begin; p < diagonal; ++p) {
            const std::uint32_t k = l.col_indices[p];
            double value = l.values[p];
            const std::size_t k_diagonal = l.row_offsets[k + 1] - 1;
            for (std::size_t q = l.row_offsets[k]; q < k_diagonal; ++q) {
                const std::size_t at = where[l.col_indices[q]];
                if (at != no_entry) value -= l.values[at] * l.values[q];
            }
            l.values[p] = value / l.values[k_diagonal];
        }
        double pivot = l.values[diagonal] * (1.0 + shift);
        for (std::size_t p = begin; p < diagonal; ++p) pivot -= l.values[p] * l.values[p];
        for (std::size_t p = begin; p < diagonal; ++p) where[l.col_indices[p]] = no_entry;
        if (!(pivot > 0.0) || !std::isfinite(pivot)) return i;
        l.values[diagonal] = std::sqrt(pivot);
    }
    return no_entry;
}

}  // namespace

Status IncompleteCholeskyPreconditioner::setup(const CsrMatrix& a) {
    factor_ = CsrMatrix{};
    shift_ = 0.0;
    if (a.rows != a.cols)
        return {Errc::invalid_argument, "incomplete Cholesky: the matrix is not square"};
    CsrMatrix lower;
    if (Status st = lower_triangle(a, lower); !st) return st;
    std::vector<std::size_t> where(a.rows, no_entry);
    double shift = 0.0;
    std::size_t failed = no_entry;
    for (int attempt = 0; attempt <= shift_attempts; ++attempt) {
        factor_ = lower;
        failed = factor_in_place(factor_, shift, where);
        if (failed == no_entry) {
            shift_ = shift;
            return Status::ok();
        }
        shift = attempt == 0 ? first_shift : shift * shift_growth;
    }
    factor_ = CsrMatrix{};
    return {Errc::numerical, "incomplete Cholesky: the pivot of row " + std::to_string(failed) +
                                 " breaks down even with a diagonal shift of " +
                                 std::to_string(shift / shift_growth)};
}

void IncompleteCholeskyPreconditioner::apply(std::span<const double> r, std::span<double> z,
                                             std::size_t k) {
    const CsrMatrix& l = factor_;
    const std::size_t n = l.rows;
    // L y = r, row by row.
    for (std::size_t i = 0; i < n; ++i) {
        const std::size_t diagonal = l.row_offsets[i + 1] - 1;
        double* zi = &z[i * k];
        for (std::size_t c = 0; c < k; ++c) zi[c] = r[i * k + c];
        for (std::size_t p = l.row_offsets[i]; p < diagonal; ++p) {
            const double* zj = &z[static_cast<std::size_t>(l.col_indices[p]) * k];
            for (std::size_t c = 0; c < k; ++c) zi[c] -= l.values[p] * zj[c];
        }
        for (std::size_t c = 0; c < k; ++c) zi[c] /= l.values[diagonal];
    }
    // Lᵀ z = y, by columns of Lᵀ (rows of L), last first.
    for (std::size_t i = n; i-- > 0;) {
        const std::size_t diagonal = l.row_offsets[i + 1] - 1;
        double* zi = &z[i * k];
        for (std::size_t c = 0; c < k; ++c) zi[c] /= l.values[diagonal];
        for (std::size_t p = l.row_offsets[i]; p < diagonal; ++p) {
            double* zj = &z[static_cast<std::size_t>(l.col_indices[p]) * k];
            for (std::size_t c = 0; c < k; ++c) zj[c] -= l.values[p] * zi[c];
        }
    }
}

}  // namespace dfm::solver
