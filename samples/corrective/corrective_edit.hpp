#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "arm.hpp"
#include "dualform/dualform.h"

// The corrective, made as a rigger makes it: with the arm posed at the bend
// where linear blend skinning fails (it pulls the elbow's cross-sections in
// towards the joint: at 120 degrees the middle one is half as wide in the
// plane of the bend), a real Dualform edit of the elbow turns seven of its
// edge loops to where the elbow's share of the bend takes them rigidly, the
// rest of the region following, and the bake keeps it as the bind-space
// corrective d = L_v^-1 D' (dualform.h, "skin and pose").
namespace corrective {

struct Corrective {
    double degrees = 0.0;          // the elbow's angle the edit was made at
    std::vector<float> delta;      // per vertex x y z: bind after the bake minus bind before
    std::vector<double> unedited;  // the pose before the edit, as Dualform showed it
    std::vector<double> edited;    // the edited pose as Dualform shows it (posed positions)
    std::size_t region_count = 0;  // vertices of the edit's ROI
    std::size_t handle_count = 0;  // of its handles (the edge loops)
    double largest_drag = 0.0;     // the farthest a handle's target is from where skinning put it
    std::uint32_t iterations = 0;  // of the solve that was baked
    dfm_skin_info skin = {};       // what the bake reports (corrective vertices, conditioning)
};

// Poses `mesh` (created from `arm`) at `degrees`, edits it and bakes. The
// mesh stays posed there, its bind pose now bind + delta. False with a
// message on stderr when the SDK refuses.
bool make(dfm_mesh* mesh, const arm::Arm& arm, double degrees, Corrective& out);

}  // namespace corrective
