#pragma once

#include <span>
#include <string_view>

#include "status/tool_status.hpp"

// Each subcommand takes the arguments after its name and returns the exit
// code (docs/scenarios.md): 0 success; 2 bad input, an argument, scenario or
// input file it cannot use; 1 failed work on accepted input, an output that
// could not be written or a solve that broke down. Both print one line
// "error: ..." on stderr.
namespace dfm::cli {

inline constexpr int exit_ok = 0;
inline constexpr int exit_failed = 1;
inline constexpr int exit_bad_input = 2;

int run_info(std::span<const std::string_view> args);
int run_convert(std::span<const std::string_view> args);
int run_deform(std::span<const std::string_view> args);
int run_bench(std::span<const std::string_view> args);
int run_pick(std::span<const std::string_view> args);
int run_roi(std::span<const std::string_view> args);
// Built with the renderer only; otherwise main says the renderer is missing.
int run_render(std::span<const std::string_view> args);

// Prints "error: <message>" on stderr and returns exit_bad_input.
int bad_input(std::string_view message);

// Prints "error: <message>" on stderr and returns exit_failed.
int failed(std::string_view message);

// A step of the work on accepted input that failed: bad input where the
// library refused what the input asked of it (DFM_ERROR_INVALID_ARGUMENT,
// _NOT_FOUND, _PARSE, _OUT_OF_RANGE, _UNSUPPORTED: a vertex the mesh does
// not have, an output format it does not write), else failed work
// (DFM_ERROR_IO, _NUMERICAL, _OUT_OF_MEMORY, ...).
int work_failure(const ToolStatus& status);

}  // namespace dfm::cli
