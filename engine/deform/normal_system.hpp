#pragma once

#include <atomic>
#include <cstdint>
#include <span>
#include <vector>

#include "core/memory_bytes.hpp"
#include "core/pooled_allocator.hpp"
#include "deform/mesh_model.hpp"
#include "solver/csr_matrix.hpp"

// The least-squares system of one edit: the dual Laplacian rows that touch
// an unknown, and the normal matrix N = AᵀA + w² H + ε I over the unknowns.
namespace dfm::deform {

// ε's weight relative to N's mean diagonal. The ε term ties what D cannot
// see (the three-colour pattern of docs/design.md) to the previous iterate;
// it vanishes at the fixed point, so it never moves the result.
inline constexpr double relative_regularization = 1e-9;

// The vertices a solve moves, numbered 0..count-1.
struct UnknownMap {
    std::vector<std::uint32_t> unknown_of_vertex;  // no_index for a fixed vertex
    std::vector<std::uint32_t> vertex_of_unknown;

    std::size_t count() const { return vertex_of_unknown.size(); }
};

struct RowEntry {
    std::uint32_t vertex;
    std::uint32_t unknown;  // no_index: a fixed vertex, moved to the right-hand side
    double coefficient;
};

struct SystemRows {
    PooledVector<std::uint32_t> faces;          // the face whose dual row each row is
    PooledVector<std::uint32_t> entry_offsets;  // entries of row r: [offsets[r], offsets[r + 1])
    PooledVector<RowEntry> entries;
    // Faces whose centroids the rows read: the rows' faces and their 1-rings.
    PooledVector<std::uint32_t> centroid_faces;

    std::size_t memory_bytes() const {
        return capacity_bytes(faces, entry_offsets, entries, centroid_faces);
    }

    std::size_t size() const { return faces.size(); }
};

SystemRows collect_rows(const MeshModel& model, const UnknownMap& unknowns);

// N's pattern from the dual rows alone (values left empty): the columns of
// row i are the unknowns of the rows that hold unknown i. The fitted
// method's rigidity rows join vertices of one dual row, so this is its
// pattern too; the analysis of the factor can start from it before the
// values are summed.
solver::CsrMatrix normal_pattern(const SystemRows& rows, std::size_t unknown_count);

// N's diagonal before AᵀA's terms: w² for each listing of an unknown in
// `soft_handles`, plus ε, `relative_epsilon` times the mean diagonal of
// AᵀA + w² H (`squares`: AᵀA's diagonal, summed in A's row order).
// Returns that start per unknown and sets `epsilon`.
std::vector<double> normal_diagonal_start(std::vector<double> squares,
                                          std::span<const std::uint32_t> soft_handles,
                                          double handle_weight, double relative_epsilon,
                                          double& epsilon);

// N built row after row: each row's terms gather in a dense accumulator,
// a term for a column already there added to it in the order given, and
// finish_row appends the row sorted by column. The accumulator holds −0,
// the sum's identity (−0 + v is v for every v, zeros of either sign
// included), so a column's first term is kept as it is, and the columns
// are listed without a branch: this is the inner loop of the set-up.
class NormalRows {
public:
    explicit NormalRows(std::size_t unknowns);

    void add(std::uint32_t column, double value) {
        columns_[count_] = column;
        count_ += seen_[column] != stamp_;
        seen_[column] = stamp_;
        sums_[column] += value;
    }
    void finish_row();
    solver::CsrMatrix take() { return std::move(n_); }

private:
    solver::CsrMatrix n_;
    std::uint32_t stamp_ = 1;  // the row being gathered, plus one
    std::size_t count_ = 0;
    std::vector<std::uint32_t> seen_;     // per column: the stamp of the row that last had it
    std::vector<double> sums_;            // per column
    std::vector<std::uint32_t> columns_;  // this row's, in the order first met, and one past
    std::vector<std::uint32_t> sorted_;   // this row's, by column
};

// N row after row: row i starts from diagonal[i], and `terms(i, rows)`
// adds its other terms (rows.add) in their order. An empty matrix once
// `stop` (optional) is set.
template <class Terms>
solver::CsrMatrix gather_normal_rows(std::span<const double> diagonal,
                                     const std::atomic<bool>* stop, Terms&& terms) {
    NormalRows rows(diagonal.size());
    for (std::uint32_t i = 0; i < diagonal.size(); ++i) {
        // A few hundred rows take well under a millisecond.
        if (stop != nullptr && i % 256 == 0 && stop->load(std::memory_order_relaxed))
            return solver::CsrMatrix{};
        rows.add(i, diagonal[i]);
        terms(i, rows);
        rows.finish_row();
    }
    return rows.take();
}

// Assembles N with sorted, duplicate-free rows. `soft_handles` are the
// unknowns tied to targets with weight `handle_weight`. ε is
// `relative_epsilon` times the mean diagonal of AᵀA + w² H, returned in
// `epsilon`: it ties the part of the solution that D cannot see (the
// three-colour pattern of docs/design.md) to the previous iterate. Once
// `stop` (optional) is true it returns an empty matrix part way.
solver::CsrMatrix assemble_normal_matrix(const SystemRows& rows, std::size_t unknown_count,
                                         std::span<const std::uint32_t> soft_handles,
                                         double handle_weight, double relative_epsilon,
                                         double& epsilon, const std::atomic<bool>* stop = nullptr);

}  // namespace dfm::deform
