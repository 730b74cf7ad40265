#pragma once

#include <span>
#include <string_view>

// Each subcommand takes the arguments after its name and returns the exit
// code: 0 success, 2 bad input (with "error: ..." on stderr), 1 failed work.
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

}  // namespace dfm::cli
