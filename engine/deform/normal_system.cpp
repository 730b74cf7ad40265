#include "deform/normal_system.hpp"
#include "core/pooled_allocator.hpp"

#include <algorithm>
#include <numeric>
#include <tuple>

namespace dfm::deform {

namespace {

// Uses ahead whose row entries the assembly prefetches: enough to cover a
// miss to memory at a few nanoseconds a use.
constexpr std::size_t prefetch_distance = 8;

// The faces whose dual rows can touch an unknown: a row reads its face's
// vertices and its neighbours'. The others' rows are never computed, so
// that a small ROI's set-up does not cost a pass of dual_row over the
// whole mesh.
std::vector<std::uint8_t> faces_near_unknowns(const MeshModel& model, const UnknownMap& unknowns) {
    const mesh::Mesh& mesh = model.mesh;
    std::vector<std::uint8_t> holds(mesh.face_count(), 0);
    for (std::uint32_t f = 0; f < mesh.face_count(); ++f)
        for (std::uint32_t v : mesh.triangles[f])
            holds[f] |= unknowns.unknown_of_vertex[v] != mesh::no_index;
    std::vector<std::uint8_t> near(holds);
    for (std::uint32_t f = 0; f < mesh.face_count(); ++f) {
        if (!model.dual.has_row[f]) continue;
        for (std::uint32_t g : model.dual.neighbors[f]) near[f] |= holds[g];
    }
    return near;
}

}  // namespace

SystemRows collect_rows(const MeshModel& model, const UnknownMap& unknowns) {
    const mesh::Mesh& mesh = model.mesh;
    SystemRows rows;
    std::vector<std::uint8_t> needs_centroid(mesh.face_count(), 0);
    const std::vector<std::uint8_t> near = faces_near_unknowns(model, unknowns);
    // A dual row has six entries at most: room for every near face's.
    const auto near_faces = static_cast<std::size_t>(std::count(near.begin(), near.end(), 1));
    rows.faces.reserve(near_faces);
    rows.entry_offsets.reserve(near_faces + 1);
    rows.entries.reserve(std::tuple_size_v<decltype(dual::DualRow::vertices)> * near_faces);
    rows.entry_offsets.push_back(0);
    for (std::uint32_t f = 0; f < mesh.face_count(); ++f) {
        if (!model.dual.has_row[f] || !near[f]) continue;
        const dual::DualRow row = dual::dual_row(mesh, model.dual, f);
        bool touches_unknown = false;
        for (std::uint32_t k = 0; k < row.size; ++k) {
            touches_unknown |= unknowns.unknown_of_vertex[row.vertices[k]] != mesh::no_index;
        }
        if (!touches_unknown) continue;
        rows.faces.push_back(f);
        for (std::uint32_t k = 0; k < row.size; ++k) {
            const std::uint32_t v = row.vertices[k];
            rows.entries.push_back({v, unknowns.unknown_of_vertex[v], row.coefficients[k]});
        }
        rows.entry_offsets.push_back(static_cast<std::uint32_t>(rows.entries.size()));
        needs_centroid[f] = 1;
        for (std::uint32_t g : model.dual.neighbors[f]) needs_centroid[g] = 1;
    }
    for (std::uint32_t f = 0; f < mesh.face_count(); ++f) {
        if (needs_centroid[f]) rows.centroid_faces.push_back(f);
    }
    return rows;
}

std::vector<double> normal_diagonal_start(std::vector<double> squares,
                                          std::span<const std::uint32_t> soft_handles,
                                          double handle_weight, double relative_epsilon,
                                          double& epsilon) {
    const std::size_t count = squares.size();
    for (std::uint32_t u : soft_handles) squares[u] += handle_weight * handle_weight;
    const double mean = count == 0 ? 0.0
                                   : std::accumulate(squares.begin(), squares.end(), 0.0) /
                                         static_cast<double>(count);
    epsilon = relative_epsilon * mean;
    std::vector<double> start(count, 0.0);
    for (std::uint32_t u : soft_handles) start[u] += handle_weight * handle_weight;
    for (double& d : start) d += epsilon;
    return start;
}

namespace {

// A row's distinct columns, in the order first met, into `sorted` by
// column: each column's place is the count of the row's columns below it,
// a few dozen compares a column without branches to miss, where a
// comparison sort would mispredict about every other one.
void sort_by_rank(std::span<const std::uint32_t> columns, std::uint32_t* sorted) {
    for (const std::uint32_t column : columns) {
        std::uint32_t rank = 0;
        for (const std::uint32_t other : columns) rank += other < column;
        sorted[rank] = column;
    }
}

}  // namespace

solver::CsrMatrix normal_pattern(const SystemRows& rows, std::size_t unknown_count) {
    std::vector<std::uint32_t> offsets(unknown_count + 1, 0);
    for (const RowEntry& e : rows.entries) {
        if (e.unknown != mesh::no_index) ++offsets[e.unknown + 1];
    }
    std::partial_sum(offsets.begin(), offsets.end(), offsets.begin());
    PooledVector<std::uint32_t> row_of(offsets.back());
    {
        std::vector<std::uint32_t> fill(offsets.begin(), offsets.end() - 1);
        for (std::uint32_t r = 0; r < rows.size(); ++r) {
            for (std::uint32_t p = rows.entry_offsets[r]; p < rows.entry_offsets[r + 1]; ++p) {
                const std::uint32_t u = rows.entries[p].unknown;
                if (u != mesh::no_index) row_of[fill[u]++] = r;
            }
        }
    }
    solver::CsrMatrix n;
    n.rows = n.cols = unknown_count;
    n.row_offsets.assign(unknown_count + 1, 0);
    n.col_indices.reserve(24 * unknown_count);
    std::vector<std::uint32_t> seen(unknown_count, mesh::no_index);
    // One past the row's columns: a column met again is written there
    // before it is found to be no new one.
    std::vector<std::uint32_t> columns(unknown_count + 1);
    std::vector<std::uint32_t> sorted(unknown_count);
    for (std::uint32_t i = 0; i < unknown_count; ++i) {
        columns[0] = i;  // N's diagonal is there even for an unknown in no row
        seen[i] = i;
        std::size_t count = 1;
        for (std::uint32_t q = offsets[i]; q < offsets[i + 1]; ++q) {
            const std::uint32_t r = row_of[q];
            for (std::uint32_t p = rows.entry_offsets[r]; p < rows.entry_offsets[r + 1]; ++p) {
                const std::uint32_t u = rows.entries[p].unknown;
                if (u == mesh::no_index) continue;
                columns[count] = u;
                count += seen[u] != i;
                seen[u] = i;
            }
        }
        sort_by_rank({columns.data(), count}, sorted.data());
        n.col_indices.insert(n.col_indices.end(), sorted.begin(),
                             sorted.begin() + static_cast<std::ptrdiff_t>(count));
        n.row_offsets[i + 1] = n.col_indices.size();
    }
    return n;
}

NormalRows::NormalRows(std::size_t unknowns)
    : seen_(unknowns, 0), sums_(unknowns, -0.0), columns_(unknowns + 1), sorted_(unknowns) {
    n_.rows = n_.cols = unknowns;
    n_.row_offsets.assign(unknowns + 1, 0);
    // A triangle mesh's vertex sees its 2-ring, 19 vertices at valence 6.
    n_.col_indices.reserve(24 * unknowns);
    n_.values.reserve(24 * unknowns);
}

void NormalRows::finish_row() {
    sort_by_rank({columns_.data(), count_}, sorted_.data());
    for (std::size_t k = 0; k < count_; ++k) {
        const std::uint32_t column = sorted_[k];
        n_.col_indices.push_back(column);
        n_.values.push_back(sums_[column]);
        sums_[column] = -0.0;
    }
    count_ = 0;
    n_.row_offsets[stamp_] = n_.col_indices.size();
    ++stamp_;
}

solver::CsrMatrix assemble_normal_matrix(const SystemRows& rows, std::size_t unknown_count,
                                         std::span<const std::uint32_t> soft_handles,
                                         double handle_weight, double relative_epsilon,
                                         double& epsilon, const std::atomic<bool>* stop) {
    // Rows touching each unknown, CSR: for each, where the row's entries
    // start and end and the unknown's coefficient in it, so that the pass
    // below reads this list in order and the rows' entries are its only
    // scattered reads.
    struct RowUse {
        std::uint32_t begin;
        std::uint32_t end;
        double coefficient;
    };
    std::vector<std::uint32_t> offsets(unknown_count + 1, 0);
    for (const RowEntry& e : rows.entries) {
        if (e.unknown != mesh::no_index) ++offsets[e.unknown + 1];
    }
    std::partial_sum(offsets.begin(), offsets.end(), offsets.begin());
    PooledVector<RowUse> uses(offsets.back());
    std::vector<double> squares(unknown_count, 0.0);
    {
        std::vector<std::uint32_t> fill(offsets.begin(), offsets.end() - 1);
        for (std::uint32_t r = 0; r < rows.size(); ++r) {
            const std::uint32_t begin = rows.entry_offsets[r];
            const std::uint32_t end = rows.entry_offsets[r + 1];
            for (std::uint32_t p = begin; p < end; ++p) {
                const RowEntry& e = rows.entries[p];
                if (e.unknown == mesh::no_index) continue;
                uses[fill[e.unknown]++] = {begin, end, e.coefficient};
                squares[e.unknown] += e.coefficient * e.coefficient;
            }
        }
    }
    const std::vector<double> diagonal = normal_diagonal_start(
        std::move(squares), soft_handles, handle_weight, relative_epsilon, epsilon);

    // Row i of N gathers, over every row of A that holds unknown i, the
    // products with that row's other unknowns.
    return gather_normal_rows(diagonal, stop, [&](std::uint32_t i, NormalRows& n) {
        for (std::uint32_t q = offsets[i]; q < offsets[i + 1]; ++q) {
            // The rows a few uses ahead are fetched while this one is summed.
            if (q + prefetch_distance < uses.size())
                __builtin_prefetch(&rows.entries[uses[q + prefetch_distance].begin]);
            const RowUse& use = uses[q];
            for (std::uint32_t s = use.begin; s < use.end; ++s) {
                const RowEntry& e = rows.entries[s];
                if (e.unknown != mesh::no_index) n.add(e.unknown, use.coefficient * e.coefficient);
            }
        }
    });
}

}  // namespace dfm::deform
