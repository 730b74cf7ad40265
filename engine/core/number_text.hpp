#pragma once

#include <string>

#include <glm/vec3.hpp>

namespace dfm {

// Appends the shortest text that reads back as exactly `value`.
void append_number(std::string& out, double value);
void append_number(std::string& out, float value);

// Appends "x y z", each number as append_number writes it.
void append_numbers(std::string& out, const glm::dvec3& v);

}  // namespace dfm
