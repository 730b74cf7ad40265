#pragma once

#include <string>

namespace dfm {

// Appends the shortest text that reads back as exactly `value`.
void append_number(std::string& out, double value);
void append_number(std::string& out, float value);

}  // namespace dfm
