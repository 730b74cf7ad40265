#include "deform/normal_system.hpp"

#include <algorithm>
#include <numeric>

namespace dfm::deform {

namespace {

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
    rows.entry_offsets.push_back(0);
    std::vector<std::uint8_t> needs_centroid(mesh.face_count(), 0);
    const std::vector<std::uint8_t> near = faces_near_unknowns(model, unknowns);
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

solver::CsrMatrix assemble_normal_matrix(const SystemRows& rows, std::size_t unknown_count,
                                         std::span<const std::uint32_t> soft_handles,
                                         double handle_weight, double relative_epsilon,
                                         double& epsilon, const std::atomic<bool>* stop) {
    // Rows touching each unknown, CSR.
    std::vector<std::uint32_t> offsets(unknown_count + 1, 0);
    for (const RowEntry& e : rows.entries) {
        if (e.unknown != mesh::no_index) ++offsets[e.unknown + 1];
    }
    std::partial_sum(offsets.begin(), offsets.end(), offsets.begin());
    std::vector<std::uint32_t> entry_of(offsets.back());
    std::vector<std::uint32_t> row_of_entry(rows.entries.size());
    std::vector<double> diagonal(unknown_count, 0.0);
    {
        std::vector<std::uint32_t> fill(offsets.begin(), offsets.end() - 1);
        for (std::uint32_t r = 0; r < rows.size(); ++r) {
            for (std::uint32_t p = rows.entry_offsets[r]; p < rows.entry_offsets[r + 1]; ++p) {
                row_of_entry[p] = r;
                const RowEntry& e = rows.entries[p];
                if (e.unknown == mesh::no_index) continue;
                entry_of[fill[e.unknown]++] = p;
                diagonal[e.unknown] += e.coefficient * e.coefficient;
            }
        }
    }
    for (std::uint32_t u : soft_handles) diagonal[u] += handle_weight * handle_weight;
    const double mean = unknown_count == 0
                            ? 0.0
                            : std::accumulate(diagonal.begin(), diagonal.end(), 0.0) /
                                  static_cast<double>(unknown_count);
    epsilon = relative_epsilon * mean;
    std::vector<double> handle_term(unknown_count, 0.0);
    for (std::uint32_t u : soft_handles) handle_term[u] += handle_weight * handle_weight;

    // Row i of N gathers, over every dual row that holds unknown i, the
    // products with that row's other unknowns: a sparse accumulator with a
    // marker per column keeps it linear in the output.
    solver::CsrMatrix n;
    n.rows = n.cols = unknown_count;
    n.row_offsets.assign(unknown_count + 1, 0);
    std::vector<std::uint32_t> slot(unknown_count, mesh::no_index);
    std::vector<std::uint32_t> cols;
    std::vector<double> vals;
    std::vector<std::uint32_t> order;
    for (std::uint32_t i = 0; i < unknown_count; ++i) {
        // A few hundred rows take well under a millisecond.
        if (stop != nullptr && i % 256 == 0 && stop->load(std::memory_order_relaxed))
            return solver::CsrMatrix{};
        cols.clear();
        vals.clear();
        auto add = [&](std::uint32_t j, double v) {
            if (slot[j] == mesh::no_index) {
                slot[j] = static_cast<std::uint32_t>(cols.size());
                cols.push_back(j);
                vals.push_back(v);
            } else {
                vals[slot[j]] += v;
            }
        };
        add(i, handle_term[i] + epsilon);
        for (std::uint32_t q = offsets[i]; q < offsets[i + 1]; ++q) {
            const std::uint32_t p = entry_of[q];
            const double ai = rows.entries[p].coefficient;
            const std::uint32_t r = row_of_entry[p];
            for (std::uint32_t s = rows.entry_offsets[r]; s < rows.entry_offsets[r + 1]; ++s) {
                const RowEntry& e = rows.entries[s];
                if (e.unknown != mesh::no_index) add(e.unknown, ai * e.coefficient);
            }
        }
        order.resize(cols.size());
        std::iota(order.begin(), order.end(), 0u);
        std::sort(order.begin(), order.end(),
                  [&](std::uint32_t a, std::uint32_t b) { return cols[a] < cols[b]; });
        for (std::uint32_t k : order) {
            n.col_indices.push_back(cols[k]);
            n.values.push_back(vals[k]);
        }
        for (std::uint32_t j : cols) slot[j] = mesh::no_index;
        n.row_offsets[i + 1] = n.col_indices.size();
    }
    return n;
}

}  // namespace dfm::deform
