#pragma once

#include <span>
#include <string>

namespace viewer {

// One line of the viewer's input help: the one table that --help, the help
// overlay and README.md's list follow.
struct KeyHelp {
    const char* input;
    const char* does;
};

std::span<const KeyHelp> mouse_help();
std::span<const KeyHelp> key_help();

// The --help text: usage, then the two tables.
std::string usage_text();

}  // namespace viewer
