#include "mesh/skin_arrays.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include <glm/matrix.hpp>

namespace dfm::mesh {

Status skin_from_arrays(std::size_t vertex_count, std::uint32_t influence_count,
                        std::span<const std::uint32_t> joints, std::span<const double> weights,
                        std::span<const glm::dmat4> inverse_bind, Skin& out) {
    out = Skin{};
    const std::size_t joint_count = inverse_bind.size();
    for (std::size_t j = 0; j < joint_count; ++j) {
        const glm::dmat4& m = inverse_bind[j];
        bool finite = true;
        for (int c = 0; c < 4; ++c) {
            for (int r = 0; r < 4; ++r) finite = finite && std::isfinite(m[c][r]);
        }
        const std::string which = "joint " + std::to_string(j) + "'s inverse bind matrix";
        if (!finite) return Status(Errc::numerical, which + " is not finite");
        if (m[0][3] != 0.0 || m[1][3] != 0.0 || m[2][3] != 0.0 || m[3][3] != 1.0) {
            return Status(Errc::invalid_argument, which +
                                                      " is not affine (its last row is not "
                                                      "0 0 0 1)");
        }
        if (std::abs(glm::determinant(m)) < 1e-30) {
            return Status(Errc::numerical, which + " is not invertible");
        }
    }
    std::vector<InfluenceList> lists(vertex_count);
    for (std::size_t v = 0; v < vertex_count; ++v) {
        double sum = 0.0;
        for (std::uint32_t k = 0; k < influence_count; ++k) {
            const std::size_t at = v * influence_count + k;
            const std::string where =
                "vertex " + std::to_string(v) + " influence " + std::to_string(k);
            if (joints[at] >= joint_count) {
                return Status(Errc::out_of_range, where + ": joint " + std::to_string(joints[at]) +
                                                      " is beyond the skin's " +
                                                      std::to_string(joint_count) + " joints");
            }
            if (!std::isfinite(weights[at]) || weights[at] < 0.0) {
                return Status(Errc::numerical, where + ": weight " + std::to_string(weights[at]) +
                                                   " is negative or not finite");
            }
            if (weights[at] == 0.0) continue;
            sum += weights[at];
            add_influence(lists[v], joints[at], weights[at]);
        }
        if (!(sum > 0.0) || !std::isfinite(sum)) {
            return Status(Errc::numerical, "vertex " + std::to_string(v) + ": its weights sum to " +
                                               std::to_string(sum) +
                                               " (they must sum to a positive number)");
        }
    }
    set_influences(lists, out);
    out.inverse_bind.assign(inverse_bind.begin(), inverse_bind.end());
    out.joint_nodes.assign(joint_count, no_index);
    out.joint_names.resize(joint_count);
    for (std::size_t j = 0; j < joint_count; ++j) out.joint_names[j] = "joint_" + std::to_string(j);
    return Status::ok();
}

}  // namespace dfm::mesh
