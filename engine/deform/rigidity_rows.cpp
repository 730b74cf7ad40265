#include "deform/rigidity_rows.hpp"

#include <algorithm>

#include <glm/geometric.hpp>
#include <glm/gtx/quaternion.hpp>

#include "deform/rotation_fit.hpp"

namespace dfm::deform {

namespace {

// The vertex of triangle `t` that is not on the edge it shares with `other`.
std::uint32_t opposite_vertex(const mesh::Triangle& t, const mesh::Triangle& other) {
    for (std::uint32_t v : t) {
        if (v != other[0] && v != other[1] && v != other[2]) return v;
    }
    return mesh::no_index;
}

// The face edges' rows against the dual edges' for an edge of mean length.
// On the camel's neck 0.1 to 0.3 fold no face (0.03 left a needle turned
// over); 0.2 keeps lengths better than 0.1 at the same iteration count
// (docs/method.md).
constexpr double relative_edge_weight = 0.2;

}  // namespace

void RotationFrames::build(const MeshModel& model, const UnknownMap& unknowns, double weight,
                           SystemRows& rows) {
    const mesh::Mesh& mesh = model.mesh;
    const std::size_t dual_rows = rows.size();
    weight_ = weight;
    first_row_ = dual_rows;
    faces_.assign(rows.faces.begin(), rows.faces.end());
    rest_dual_.resize(dual_rows);
    rigid_offsets_.assign(1, 0);
    rest_vectors_.clear();
    rotations_.assign(dual_rows, glm::dquat(1.0, 0.0, 0.0, 0.0));
    saved_ = rotations_;
    std::vector<glm::dvec3> rest(mesh.face_count());
    dual::compute_centroids(mesh, mesh.positions, rest);
    auto add = [&](std::uint32_t c, std::uint32_t d, double scale, std::uint32_t f) {
        const std::uint32_t uc = unknowns.unknown_of_vertex[c];
        const std::uint32_t ud = unknowns.unknown_of_vertex[d];
        if (uc == mesh::no_index && ud == mesh::no_index) return;
        rows.faces.push_back(f);
        rows.entries.push_back({c, uc, weight * scale});
        rows.entries.push_back({d, ud, -weight * scale});
        rows.entry_offsets.push_back(static_cast<std::uint32_t>(rows.entries.size()));
        rest_vectors_.push_back(scale * (mesh.positions[c] - mesh.positions[d]));
    };
    // Edge rows are relative: a needle's short edge gets the weight of its
    // shortness. Lengths alone would let needles (the camel's head has edges
    // 70 times shorter than their neighbours) turn over at no cost.
    double mean_edge = 0.0;
    for (const auto& e : model.topology.edges) {
        mean_edge += glm::length(mesh.positions[e[0]] - mesh.positions[e[1]]);
    }
    mean_edge /= static_cast<double>(std::max<std::size_t>(model.topology.edges.size(), 1));
    for (std::size_t r = 0; r < dual_rows; ++r) {
        const std::uint32_t f = faces_[r];
        const mesh::Triangle& t = mesh.triangles[f];
        rest_dual_[r] = dual::dual_coordinate(model.dual, rest, f);
        if (weight > 0.0) {
            for (int k = 0; k < 3; ++k) {
                const std::uint32_t j = model.dual.neighbors[f][k];
                const std::uint32_t c = opposite_vertex(t, mesh.triangles[j]);
                const std::uint32_t d = opposite_vertex(mesh.triangles[j], t);
                if (c != mesh::no_index && d != mesh::no_index) add(c, d, 1.0 / 3.0, f);
                const std::uint32_t a = t[k];
                const std::uint32_t b = t[(k + 1) % 3];
                const double length = glm::length(mesh.positions[a] - mesh.positions[b]);
                if (length > 0.0) add(a, b, relative_edge_weight * mean_edge / length, f);
            }
        }
        rigid_offsets_.push_back(static_cast<std::uint32_t>(rest_vectors_.size()));
    }
}

namespace {

// Row r's product with the positions, whole and its fixed part alone.
struct RowProduct {
    glm::dvec3 whole{0.0};
    glm::dvec3 fixed{0.0};
};

RowProduct row_product(const SystemRows& rows, std::size_t r,
                       std::span<const glm::dvec3> positions) {
    RowProduct out;
    for (std::uint32_t p = rows.entry_offsets[r]; p < rows.entry_offsets[r + 1]; ++p) {
        const RowEntry& e = rows.entries[p];
        const glm::dvec3 term = e.coefficient * positions[e.vertex];
        out.whole += term;
        if (e.unknown == mesh::no_index) out.fixed += term;
    }
    return out;
}

// Adds row r's share of Aᵀ (t − A_fixed p_fixed) to rhs; returns |A p − t|².
double assemble_row(const SystemRows& rows, std::size_t r, const RowProduct& product,
                    const glm::dvec3& target, std::span<double> rhs) {
    const glm::dvec3 b = target - product.fixed;
    for (std::uint32_t p = rows.entry_offsets[r]; p < rows.entry_offsets[r + 1]; ++p) {
        const RowEntry& e = rows.entries[p];
        if (e.unknown == mesh::no_index) continue;
        for (int c = 0; c < 3; ++c) rhs[3 * e.unknown + c] += e.coefficient * b[c];
    }
    const glm::dvec3 residual = product.whole - target;
    return glm::dot(residual, residual);
}

// The same for a rigidity row, whose two entries are known to be there.
RowProduct pair_product(const SystemRows& rows, std::size_t r,
                        std::span<const glm::dvec3> positions) {
    const RowEntry& a = rows.entries[rows.entry_offsets[r]];
    const RowEntry& b = rows.entries[rows.entry_offsets[r] + 1];
    const glm::dvec3 ta = a.coefficient * positions[a.vertex];
    const glm::dvec3 tb = b.coefficient * positions[b.vertex];
    RowProduct out;
    out.whole = ta + tb;
    if (a.unknown == mesh::no_index) out.fixed += ta;
    if (b.unknown == mesh::no_index) out.fixed += tb;
    return out;
}

double assemble_pair(const SystemRows& rows, std::size_t r, const RowProduct& product,
                     const glm::dvec3& target, std::span<double> rhs) {
    const glm::dvec3 b = target - product.fixed;
    for (std::uint32_t p = rows.entry_offsets[r]; p < rows.entry_offsets[r] + 2; ++p) {
        const RowEntry& e = rows.entries[p];
        if (e.unknown == mesh::no_index) continue;
        double* out = &rhs[3 * e.unknown];
        out[0] += e.coefficient * b.x;
        out[1] += e.coefficient * b.y;
        out[2] += e.coefficient * b.z;
    }
    const glm::dvec3 residual = product.whole - target;
    return glm::dot(residual, residual);
}

}  // namespace

double RotationFrames::fit_and_assemble(const SystemRows& rows,
                                        std::span<const glm::dvec3> positions,
                                        std::span<const double> height_scale, int steps,
                                        std::span<double> rhs) {
    std::fill(rhs.begin(), rhs.end(), 0.0);
    double energy = 0.0;
    std::array<RowProduct, max_rigidity_rows> rigid{};
    for (std::size_t r = 0; r < faces_.size(); ++r) {
        const double scale = height_scale.empty() ? 1.0 : height_scale[r];
        const glm::dvec3 rest_dual = scale * rest_dual_[r];
        const RowProduct dual = row_product(rows, r, positions);
        glm::dmat3 covariance = glm::outerProduct(dual.whole, rest_dual);
        const std::uint32_t first = rigid_offsets_[r];
        const std::uint32_t count = rigid_offsets_[r + 1] - first;
        for (std::uint32_t k = 0; k < count; ++k) {
            rigid[k] = pair_product(rows, first_row_ + first + k, positions);
            // The row holds w times the vector: w² in the covariance.
            covariance += weight_ * glm::outerProduct(rigid[k].whole, rest_vectors_[first + k]);
        }
        fit_rotation(covariance, rotations_[r], steps);
        const glm::dmat3 rotation = glm::mat3_cast(rotations_[r]);
        energy += assemble_row(rows, r, dual, rotation * rest_dual, rhs);
        for (std::uint32_t k = 0; k < count; ++k) {
            energy += assemble_pair(rows, first_row_ + first + k, rigid[k],
                                    weight_ * (rotation * rest_vectors_[first + k]), rhs);
        }
    }
    return energy;
}

}  // namespace dfm::deform
