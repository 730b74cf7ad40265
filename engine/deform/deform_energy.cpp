#include "deform/deform_energy.hpp"

#include <glm/geometric.hpp>

namespace dfm::deform {

double add_handle_terms(std::span<const glm::dvec3> positions, const UnknownMap& unknowns,
                        std::span<const std::uint32_t> soft_handles,
                        std::span<const glm::dvec3> handle_targets, double handle_weight,
                        double epsilon, std::span<double> rhs) {
    double energy = 0.0;
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
