#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include <glm/gtc/quaternion.hpp>

#include "core/memory_bytes.hpp"
#include "deform/mesh_model.hpp"
#include "deform/normal_system.hpp"

// The default method's local step (docs/method.md). Each dual row f gets a
// rotation R_f fitted to its dual 1-ring, and its rows follow it: the dual
// Laplacian row asks for R_f l_f (the rest coordinate turned, where the paper
// takes the plane normal), and rigidity rows ask each dual edge c_f − c_j
// and each edge of f to equal R_f times its rest vector. The dual Laplacian
// rows keep the detail; the rigidity rows keep the lengths that those rows
// leave free, so a large bend turns the surface instead of folding it. As f
// and j share an edge, c_f − c_j = (v_c − v_d) / 3 for the two vertices
// opposite it: every rigidity row has two entries inside the dual rows'
// 2-ring, and the normal matrix keeps its sparsity pattern.
namespace dfm::deform {

class RotationFrames {
public:
    // Appends the rigidity rows of each dual row of `rows` (those that touch
    // an unknown), weighted by `weight` against the dual Laplacian rows, and
    // starts every rotation at the identity. `rows` must hold the dual rows
    // alone on entry.
    void build(const MeshModel& model, const UnknownMap& unknowns, double weight, SystemRows& rows);

    // The local step, and the global step's right-hand side in the same
    // pass: fits each dual row's rotation to `positions` (the whole mesh),
    // starting from the last fit with at most `steps` Newton steps, then
    // writes rhs = Aᵀ (t − A_fixed p_fixed) for the rows' targets t (3
    // interleaved columns) and returns Σ_r |A_r p − t_r|², the rows' share
    // of the energy (deform_energy.hpp). A fit never raises the energy of
    // its rows over the previous rotations. `height_scale`, when not empty,
    // scales each dual row's target (DeformSettings::scale_heights).
    double fit_and_assemble(const SystemRows& rows, std::span<const glm::dvec3> positions,
                            std::span<const double> height_scale, int steps, std::span<double> rhs);

    // Keeps the current rotations, and goes back to them: a refused trial
    // step must not become the next fit's starting point.
    void remember() { saved_ = rotations_; }
    void recall() { rotations_ = saved_; }

    std::size_t dual_rows() const { return rest_dual_.size(); }
    std::size_t memory_bytes() const {
        return capacity_bytes(faces_, rest_dual_, rigid_offsets_, rest_vectors_, rotations_,
                              saved_);
    }

private:
    static constexpr std::size_t max_rigidity_rows = 6;  // per dual row: 3 dual, 3 face edges
    double weight_ = 0.0;
    std::size_t first_row_ = 0;                 // the first rigidity row in the system
    std::vector<std::uint32_t> faces_;          // per dual row
    std::vector<glm::dvec3> rest_dual_;         // l_f at rest, per dual row
    std::vector<std::uint32_t> rigid_offsets_;  // dual row r's rigidity rows: [r], [r + 1]
    std::vector<glm::dvec3> rest_vectors_;      // per rigidity row, unweighted
    std::vector<glm::dquat> rotations_;         // per dual row
    std::vector<glm::dquat> saved_;
};

}  // namespace dfm::deform
