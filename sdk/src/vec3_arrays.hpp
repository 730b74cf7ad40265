#pragma once

#include <cstddef>
#include <cstring>
#include <span>
#include <string>
#include <type_traits>

#include <glm/vec3.hpp>

#include "dualform/dualform.h"

namespace dfm::sdk {

// Whether a host's scalar type field holds one of the enum's values. Read as
// its integer: C lets a host store any int there, and loading an invalid
// value as the C++ enum is undefined.
inline bool known_scalar_type(const dfm_scalar_type& field) {
    std::underlying_type_t<dfm_scalar_type> raw;
    std::memcpy(&raw, &field, sizeof raw);
    return raw == DFM_SCALAR_FLOAT32 || raw == DFM_SCALAR_FLOAT64;
}

// Checks a host array descriptor: data present, a known scalar type, a
// stride that holds one vector. `what` names it in the message; empty
// string when it is fine.
std::string check_vec3_input(const dfm_vec3_input* in, const char* what);
// The same for an output that must hold `needed` vectors.
std::string check_vec3_output(const dfm_vec3_output* out, std::size_t needed, const char* what);

glm::dvec3 read_vec3(const dfm_vec3_input& in, std::size_t i);
void write_vec3(const dfm_vec3_output& out, std::size_t i, const glm::dvec3& v);
// Writes `values` to entries first, first + 1, ... with the type decided
// once, not per vector: the hot path of a host's per-frame read.
void write_vec3_range(const dfm_vec3_output& out, std::size_t first,
                      std::span<const glm::dvec3> values);

}  // namespace dfm::sdk
