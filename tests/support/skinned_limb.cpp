#include "support/skinned_limb.hpp"

#include <algorithm>
#include <cmath>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/matrix.hpp>

#include "support/gltf_builder.hpp"
#include "support/procedural_meshes.hpp"

namespace dfm::test {

glm::dmat4 elbow_world(const SkinnedLimb& limb, double degrees) {
    return glm::rotate(glm::translate(glm::dmat4(1.0), glm::dvec3(0.0, limb.length / 2, 0.0)),
                       glm::radians(degrees), glm::dvec3(0.0, 0.0, 1.0));
}

SkinnedLimb make_skinned_limb(int segments, int rings) {
    SkinnedLimb limb;
    limb.length = 2.0;
    limb.radius = 0.2;
    limb.mesh = rounded_to_float(make_limb(segments, rings, limb.radius, limb.length));
    const std::size_t n = limb.mesh.vertex_count();
    limb.inverse_bind = {glm::dmat4(1.0), glm::inverse(elbow_world(limb, 0.0))};
    std::vector<std::uint8_t> joints;
    std::vector<float> weights;
    std::vector<float> flex;
    for (std::size_t v = 0; v < n; ++v) {
        const glm::dvec3 p = limb.mesh.positions[v];
        const double t = std::clamp((p.y - 0.4 * limb.length) / (0.2 * limb.length), 0.0, 1.0);
        limb.joints.push_back({0, 1});
        joints.insert(joints.end(), {0, 1, 0, 0});
        weights.insert(weights.end(),
                       {1.0f - static_cast<float>(t), static_cast<float>(t), 0.0f, 0.0f});
        limb.weights.push_back({weights[4 * v], weights[4 * v + 1]});
        glm::dvec3 d(0.0);
        if (p.y > 0.5 * limb.length && std::hypot(p.x, p.z) > 0.0) {
            d = glm::dvec3(p.x, 0.0, p.z) * 0.1;
        }
        for (int c = 0; c < 3; ++c) flex.push_back(static_cast<float>(d[c]));
        limb.flex.push_back(glm::dvec3(flex[3 * v], flex[3 * v + 1], flex[3 * v + 2]));
    }
    std::vector<std::uint32_t> indices;
    for (const mesh::Triangle& t : limb.mesh.triangles)
        indices.insert(indices.end(), t.begin(), t.end());
    std::vector<float> ibm;
    for (const glm::dmat4& m : limb.inverse_bind) {
        for (int c = 0; c < 4; ++c) {
            for (int r = 0; r < 4; ++r) ibm.push_back(static_cast<float>(m[c][r]));
        }
    }
    GltfBuilder b;
    const int position = b.positions(float_positions(limb.mesh));
    const int index = b.indices_u32(indices);
    const int joint = b.accessor(b.view_of(joints), 5121, n, "VEC4");
    const int weight = b.floats(weights, "VEC4");
    const int flex_accessor = b.floats(flex, "VEC3");
    const int ibm_accessor = b.accessor(b.view_of(ibm), 5126, limb.inverse_bind.size(), "MAT4");
    const float s = std::sqrt(0.5f);
    const int bend_times = b.floats({0.0f, 1.0f}, "SCALAR");
    const int bend_values = b.floats({0, 0, 0, 1, 0, 0, s, s}, "VEC4");
    const int step_times = b.floats({0.0f, 0.5f}, "SCALAR");
    const int step_values = b.floats({0, 0, 0, 0.1f, 0, 0}, "VEC3");
    const int flex_values = b.floats({0.25f, 1.0f}, "SCALAR");
    const int spline_times = b.floats({0.0f, 2.0f}, "SCALAR");
    const int spline_values =
        b.floats({0, 0, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, s, s, 0, 0, 0, 0}, "VEC4");
    b.members =
        "\"scene\":0,\"scenes\":[{\"nodes\":[0,1]}],"
        "\"nodes\":[{\"name\":\"Arm\",\"mesh\":0,\"skin\":0},"
        "{\"name\":\"Shoulder\",\"children\":[2]},"
        "{\"name\":\"Elbow\",\"translation\":[0," +
        std::to_string(limb.length / 2) +
        ",0]}],"
        "\"skins\":[{\"joints\":[1,2],\"inverseBindMatrices\":" +
        std::to_string(ibm_accessor) +
        "}],"
        "\"meshes\":[{\"name\":\"Arm\",\"weights\":[0.25],\"extras\":{\"targetNames\":[\"Flex\"]},"
        "\"primitives\":[{\"attributes\":{\"POSITION\":" +
        std::to_string(position) + ",\"JOINTS_0\":" + std::to_string(joint) +
        ",\"WEIGHTS_0\":" + std::to_string(weight) + "},\"indices\":" + std::to_string(index) +
        ",\"targets\":[{\"POSITION\":" + std::to_string(flex_accessor) +
        "}]}]}],"
        "\"animations\":[{\"name\":\"Bend\",\"samplers\":["
        "{\"input\":" +
        std::to_string(bend_times) + ",\"output\":" + std::to_string(bend_values) +
        "},{\"input\":" + std::to_string(step_times) +
        ",\"output\":" + std::to_string(step_values) +
        ",\"interpolation\":\"STEP\"},{\"input\":" + std::to_string(bend_times) +
        ",\"output\":" + std::to_string(flex_values) +
        "}],\"channels\":[{\"sampler\":0,\"target\":{\"node\":2,\"path\":\"rotation\"}},"
        "{\"sampler\":1,\"target\":{\"node\":1,\"path\":\"translation\"}},"
        "{\"sampler\":2,\"target\":{\"node\":0,\"path\":\"weights\"}}]},"
        "{\"name\":\"Spline\",\"samplers\":[{\"input\":" +
        std::to_string(spline_times) + ",\"output\":" + std::to_string(spline_values) +
        ",\"interpolation\":\"CUBICSPLINE\"}],"
        "\"channels\":[{\"sampler\":0,\"target\":{\"node\":2,\"path\":\"rotation\"}}]}]";
    limb.glb = b.glb();
    return limb;
}

}  // namespace dfm::test
