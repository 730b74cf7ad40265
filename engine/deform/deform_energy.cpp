#include "deform/deform_energy.hpp"

#include <glm/geometric.hpp>

namespace dfm::deform {

double write_handle_terms(std::span<const double> x, std::span<const std::uint32_t> soft_handles,
                          std::span<const glm::dvec3> handle_targets, double handle_weight,
                          double epsilon, std::span<double> rhs) {
    for (std::size_t j = 0; j < rhs.size(); ++j) rhs[j] = epsilon * x[j];
    double energy = 0.0;
    const double w2 = handle_weight * handle_weight;
    for (std::size_t h = 0; h < soft_handles.size(); ++h) {
        const std::size_t u = 3 * soft_handles[h];
        const glm::dvec3 miss = glm::dvec3(x[u], x[u + 1], x[u + 2]) - handle_targets[h];
        energy += w2 * glm::dot(miss, miss);
        for (int c = 0; c < 3; ++c) rhs[u + c] += w2 * handle_targets[h][c];
    }
    return energy;
}

}  // namespace dfm::deform
