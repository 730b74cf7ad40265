#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "arm.hpp"
#include "corrective_edit.hpp"
#include "dualform/dualform.h"

// What the sample draws: the arm twice, skinned by the host each frame with
// the same joint matrices, skinning alone on the left and with the
// corrective on the right, as one mesh for the renderer.
namespace scene {

// The pose-space driver: how much of the corrective the elbow's angle asks
// for, 0 straight, 1 at the angle it was edited at.
double driver_weight(double degrees, double edited_degrees);

struct Scene {
    static constexpr double gap = 2.7;     // along x, between the copies' origins
    std::size_t n = 0;                     // vertices of one copy
    std::vector<double> plain, corrected;  // each copy as skinned, x y z per vertex
    std::vector<double> positions;         // both, placed side by side
    std::vector<std::uint32_t> indices;    // both copies' triangles

    explicit Scene(const arm::Arm& arm);

    // Skins both copies with the elbow at `degrees`, the corrected one with
    // driver_weight's share of the corrective.
    void pose(const arm::Arm& arm, const corrective::Corrective& fix, double degrees);

    dfm_vec3_input input() const { return {positions.data(), 2 * n, 0, DFM_SCALAR_FLOAT64}; }
};

// A camera looking straight down -z at all of `positions` (x y z), filling a
// width x height picture: both copies seen alike, neither nearer.
dfm_camera front_camera(const std::vector<double>& positions, int width, int height);

}  // namespace scene
