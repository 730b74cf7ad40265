#include "skin_input.hpp"

#include <cstdint>
#include <cstring>
#include <string>
#include <type_traits>
#include <vector>

#include <glm/gtc/type_ptr.hpp>

#include "mesh/skin_arrays.hpp"
#include "vec3_arrays.hpp"

namespace dfm::sdk {

namespace {

std::size_t index_size(std::underlying_type_t<dfm_index_type> type) {
    switch (type) {
        case DFM_INDEX_UINT32: return 4;
        case DFM_INDEX_UINT16: return 2;
        case DFM_INDEX_UINT8: return 1;
        default: return 0;
    }
}

std::uint32_t read_index(const unsigned char* p, std::size_t size) {
    if (size == 1) return *p;
    if (size == 2) {
        std::uint16_t v;
        std::memcpy(&v, p, sizeof v);
        return v;
    }
    std::uint32_t v;
    std::memcpy(&v, p, sizeof v);
    return v;
}

}  // namespace

Status read_skin_input(const dfm_skin_input& in, std::size_t vertex_count, mesh::Skin& out) {
    if (in.joint_count > DFM_MAX_JOINTS) {
        return Status(Errc::invalid_argument, "desc->skin.joint_count " +
                                                  std::to_string(in.joint_count) +
                                                  " is more than DFM_MAX_JOINTS (65536)");
    }
    if (in.influence_count == 0 || in.influence_count > DFM_MAX_INFLUENCES) {
        return Status(Errc::invalid_argument, "desc->skin.influence_count " +
                                                  std::to_string(in.influence_count) +
                                                  " is not between 1 and DFM_MAX_INFLUENCES (32)");
    }
    if (in.inverse_bind_matrices == nullptr || in.joints == nullptr || in.weights == nullptr) {
        return Status(Errc::invalid_argument,
                      std::string("desc->skin.") +
                          (in.inverse_bind_matrices == nullptr ? "inverse_bind_matrices"
                           : in.joints == nullptr              ? "joints"
                                                               : "weights") +
                          " is NULL");
    }
    std::underlying_type_t<dfm_index_type> joint_type;
    std::memcpy(&joint_type, &in.joint_type, sizeof joint_type);
    const std::size_t joint_size = index_size(joint_type);
    if (joint_size == 0) {
        return Status(Errc::invalid_argument,
                      "desc->skin.joint_type " + std::to_string(joint_type) + " is unknown");
    }
    if (!known_scalar_type(in.weight_type)) {
        return Status(Errc::invalid_argument, "desc->skin.weight_type is unknown");
    }
    const std::size_t weight_size = in.weight_type == DFM_SCALAR_FLOAT64 ? 8 : 4;
    const std::size_t joint_row = in.influence_count * joint_size;
    const std::size_t weight_row = in.influence_count * weight_size;
    if (in.joint_stride != 0 && in.joint_stride < joint_row) {
        return Status(Errc::invalid_argument, "desc->skin.joint_stride " +
                                                  std::to_string(in.joint_stride) +
                                                  " is smaller than one vertex's joints (" +
                                                  std::to_string(joint_row) + " bytes)");
    }
    if (in.weight_stride != 0 && in.weight_stride < weight_row) {
        return Status(Errc::invalid_argument, "desc->skin.weight_stride " +
                                                  std::to_string(in.weight_stride) +
                                                  " is smaller than one vertex's weights (" +
                                                  std::to_string(weight_row) + " bytes)");
    }
    const std::size_t joint_stride = in.joint_stride != 0 ? in.joint_stride : joint_row;
    const std::size_t weight_stride = in.weight_stride != 0 ? in.weight_stride : weight_row;
    const auto* joint_bytes = static_cast<const unsigned char*>(in.joints);
    const auto* weight_bytes = static_cast<const unsigned char*>(in.weights);
    const std::size_t n = static_cast<std::size_t>(in.influence_count) * vertex_count;
    std::vector<std::uint32_t> joints(n);
    std::vector<double> weights(n);
    for (std::size_t v = 0; v < vertex_count; ++v) {
        for (std::uint32_t k = 0; k < in.influence_count; ++k) {
            const std::size_t at = v * in.influence_count + k;
            joints[at] = read_index(joint_bytes + v * joint_stride + k * joint_size, joint_size);
            const unsigned char* w = weight_bytes + v * weight_stride + k * weight_size;
            if (weight_size == 8) {
                std::memcpy(&weights[at], w, 8);
            } else {
                float f;
                std::memcpy(&f, w, 4);
                weights[at] = f;
            }
        }
    }
    std::vector<glm::dmat4> inverse_bind(in.joint_count);
    for (std::uint32_t j = 0; j < in.joint_count; ++j) {
        inverse_bind[j] =
            glm::make_mat4(in.inverse_bind_matrices + 16 * static_cast<std::size_t>(j));
    }
    if (Status s = mesh::skin_from_arrays(vertex_count, in.influence_count, joints, weights,
                                          inverse_bind, out);
        !s) {
        return Status(s.code(), "desc->skin: " + s.message());
    }
    return Status::ok();
}

}  // namespace dfm::sdk
