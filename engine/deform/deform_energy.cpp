#include "deform/deform_energy.hpp"

#include <algorithm>

#include <glm/geometric.hpp>

namespace dfm::deform {

double right_hand_side_and_energy(const SystemRows& rows, std::span<const glm::dvec3> targets,
                                  std::span<const glm::dvec3> positions, const UnknownMap& unknowns,
                                  std::span<const std::uint32_t> soft_handles,
                                  std::span<const glm::dvec3> handle_targets, double handle_weight,
                                  double epsilon, std::span<double> rhs) {
    std::fill(rhs.begin(), rhs.end(), 0.0);
    double energy = 0.0;
    for (std::size_t r = 0; r < rows.size(); ++r) {
        glm::dvec3 b = targets[r];
        glm::dvec3 moving(0.0);
        for (std::uint32_t p = rows.entry_offsets[r]; p < rows.entry_offsets[r + 1]; ++p) {
            const RowEntry& e = rows.entries[p];
            if (e.unknown == mesh::no_index) {
                b -= e.coefficient * positions[e.vertex];
            } else {
                moving += e.coefficient * positions[e.vertex];
            }
        }
        const glm::dvec3 residual = moving - b;
        energy += glm::dot(residual, residual);
        for (std::uint32_t p = rows.entry_offsets[r]; p < rows.entry_offsets[r + 1]; ++p) {
            const RowEntry& e = rows.entries[p];
            if (e.unknown == mesh::no_index) continue;
            for (int c = 0; c < 3; ++c) rhs[3 * e.unknown + c] += e.coefficient * b[c];
        }
    }
    const double w2 = handle_weight * handle_weight;
    for (std::size_t h = 0; h < soft_handles.size(); ++h) {
        const glm::dvec3 miss =
            positions[unknowns.vertex_of_unknown[soft_handles[h]]] - handle_targets[h];
        energy += w2 * glm::dot(miss, miss);
        for (int c = 0; c < 3; ++c) rhs[3 * soft_handles[h] + c] += w2 * handle_targets[h][c];
    }
    for (std::size_t i = 0; i < unknowns.count(); ++i) {
        const glm::dvec3& p = positions[unknowns.vertex_of_unknown[i]];
        for (int c = 0; c < 3; ++c) rhs[3 * i + c] += epsilon * p[c];
    }
    return energy;
}

}  // namespace dfm::deform
