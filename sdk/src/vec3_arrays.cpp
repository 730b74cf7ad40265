#include "vec3_arrays.hpp"

#include <cstring>

namespace dfm::sdk {

namespace {

std::size_t scalar_size(dfm_scalar_type type) {
    return type == DFM_SCALAR_FLOAT64 ? sizeof(double) : sizeof(float);
}

std::string check_layout(const void* data, const dfm_scalar_type& type, std::size_t stride,
                         const char* what) {
    std::string message;
    if (data == nullptr) {
        message = what;
        message += ": data is NULL";
    } else if (!known_scalar_type(type)) {
        message = what;
        message += ": unknown scalar type (DFM_SCALAR_FLOAT32 or DFM_SCALAR_FLOAT64 expected)";
    } else if (stride != 0 && stride < 3 * scalar_size(type)) {
        message = what;
        message += ": stride " + std::to_string(stride) + " is smaller than one vector (" +
                   std::to_string(3 * scalar_size(type)) + " bytes)";
    }
    return message;
}

std::size_t stride_of(std::size_t stride, dfm_scalar_type type) {
    return stride != 0 ? stride : 3 * scalar_size(type);
}

}  // namespace

std::string check_vec3_input(const dfm_vec3_input* in, const char* what) {
    if (in == nullptr) return std::string(what) + " is NULL";
    return check_layout(in->data, in->type, in->stride, what);
}

std::string check_vec3_output(const dfm_vec3_output* out, std::size_t needed, const char* what) {
    if (out == nullptr) return std::string(what) + " is NULL";
    std::string message = check_layout(out->data, out->type, out->stride, what);
    if (message.empty() && out->count < needed) {
        message = what;
        message += ": room for " + std::to_string(out->count) + " vectors, " +
                   std::to_string(needed) + " needed";
    }
    return message;
}

glm::dvec3 read_vec3(const dfm_vec3_input& in, std::size_t i) {
    const char* p = static_cast<const char*>(in.data) + i * stride_of(in.stride, in.type);
    if (in.type == DFM_SCALAR_FLOAT64) {
        double v[3];
        std::memcpy(v, p, sizeof v);
        return {v[0], v[1], v[2]};
    }
    float v[3];
    std::memcpy(v, p, sizeof v);
    return {v[0], v[1], v[2]};
}

void write_vec3(const dfm_vec3_output& out, std::size_t i, const glm::dvec3& v) {
    char* p = static_cast<char*>(out.data) + i * stride_of(out.stride, out.type);
    if (out.type == DFM_SCALAR_FLOAT64) {
        const double d[3] = {v.x, v.y, v.z};
        std::memcpy(p, d, sizeof d);
    } else {
        const float f[3] = {static_cast<float>(v.x), static_cast<float>(v.y),
                            static_cast<float>(v.z)};
        std::memcpy(p, f, sizeof f);
    }
}

void write_vec3_range(const dfm_vec3_output& out, std::size_t first,
                      std::span<const glm::dvec3> values) {
    const std::size_t stride = stride_of(out.stride, out.type);
    char* p = static_cast<char*>(out.data) + first * stride;
    if (out.type == DFM_SCALAR_FLOAT64) {
        if (stride == sizeof(glm::dvec3)) {
            std::memcpy(p, values.data(), values.size_bytes());
            return;
        }
        for (const glm::dvec3& v : values) {
            std::memcpy(p, &v, sizeof v);
            p += stride;
        }
        return;
    }
    for (const glm::dvec3& v : values) {
        const float f[3] = {static_cast<float>(v.x), static_cast<float>(v.y),
                            static_cast<float>(v.z)};
        std::memcpy(p, f, sizeof f);
        p += stride;
    }
}

}  // namespace dfm::sdk
