#pragma once

#include <cstddef>
#include <span>
#include <string>

#include <glm/vec3.hpp>

#include "dualform/dualform.h"

namespace dfm::sdk {

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
