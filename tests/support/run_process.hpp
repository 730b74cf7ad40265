#pragma once

#include <string>
#include <vector>

namespace dfm::test {

struct ProcessResult {
    int exit_code = -1;  // -1 when killed by a signal
    std::string out;
    std::string err;
};

// Runs a program with arguments (no shell interpretation of them) and
// captures what it prints.
ProcessResult run_process(const std::string& program, const std::vector<std::string>& args);

}  // namespace dfm::test
