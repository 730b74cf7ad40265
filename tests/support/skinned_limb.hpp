#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include <glm/mat4x4.hpp>

#include "mesh/mesh.hpp"

// A skinned limb made in code, for the skin and pose tests: make_limb's
// capped cylinder along +y, bound to two joints (the shoulder at the origin,
// the elbow at half its length), its weights blending over the middle fifth,
// and as a glTF asset:
//   nodes: 0 "Arm" (mesh 0, skin 0), 1 "Shoulder" (joint 0) with child
//          2 "Elbow" (joint 1) at (0, length / 2, 0); scene roots 0 and 1;
//   mesh 0: one primitive, JOINTS_0 (unsigned bytes) and WEIGHTS_0 (floats),
//           the morph target "Flex" (the upper half pushed out radially by
//           0.1 of the radius) with default weight 0.25;
//   animation 0 "Bend": the elbow turns about +z from 0 to 90 degrees over
//           [0, 1] (LINEAR); the shoulder steps to (0.1, 0, 0) at 0.5 (STEP);
//           "Flex" goes from 0.25 to 1 over [0, 1] (LINEAR, node 0 weights);
//   animation 1 "Spline": the elbow turns about +z from 0 to 90 degrees over
//           [0, 2], CUBICSPLINE with zero tangents.
namespace dfm::test {

struct SkinnedLimb {
    mesh::Mesh mesh;  // the bind pose, double (the glTF holds it as float)
    std::vector<std::array<std::uint32_t, 2>> joints;  // per vertex
    std::vector<std::array<double, 2>> weights;
    std::vector<glm::dmat4> inverse_bind;  // per joint
    std::vector<glm::dvec3> flex;          // "Flex"'s delta per vertex
    double length = 0.0;
    double radius = 0.0;
    std::string glb;
};

SkinnedLimb make_skinned_limb(int segments, int rings);

// Joint 1's world matrix with the elbow turned by `degrees` about +z.
glm::dmat4 elbow_world(const SkinnedLimb& limb, double degrees);

}  // namespace dfm::test
