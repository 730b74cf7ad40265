#include <cstdio>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "dualform/commands.hpp"
#include "dualform/usage.hpp"

namespace dfm::cli {

int bad_input(std::string_view message) {
    std::fprintf(stderr, "error: %.*s\n", static_cast<int>(message.size()), message.data());
    return exit_bad_input;
}

int failed(std::string_view message) {
    std::fprintf(stderr, "error: %.*s\n", static_cast<int>(message.size()), message.data());
    return exit_failed;
}

int work_failure(const ToolStatus& status) {
    switch (status.code()) {
        case DFM_ERROR_INVALID_ARGUMENT:
        case DFM_ERROR_NOT_FOUND:
        case DFM_ERROR_PARSE:
        case DFM_ERROR_OUT_OF_RANGE:
        case DFM_ERROR_UNSUPPORTED: return bad_input(status.message());
        default: return failed(status.message());
    }
}

namespace {

// The command's usage on stdout when its arguments ask for it.
std::optional<int> help_asked(const CommandHelp& command, std::span<const std::string_view> args) {
    if (!asks_for_help(args)) return std::nullopt;
    std::printf("%s\n", usage(command).c_str());
    return exit_ok;
}

}  // namespace

}  // namespace dfm::cli

int main(int argc, char** argv) {
    using namespace dfm::cli;
    try {
        if (argc < 2) {
            std::fputs(help_text().c_str(), stderr);
            return exit_bad_input;
        }
        const std::string_view command = argv[1];
        const std::vector<std::string_view> args(argv + 2, argv + argc);
        using Run = int (*)(std::span<const std::string_view>);
        const std::pair<const CommandHelp*, Run> commands[] = {
            {&info_help, run_info},   {&convert_help, run_convert}, {&deform_help, run_deform},
            {&bench_help, run_bench}, {&pick_help, run_pick},       {&roi_help, run_roi},
        };
        for (const auto& [help, run] : commands) {
            if (command != help->name) continue;
            if (const std::optional<int> code = help_asked(*help, args)) return *code;
            return run(args);
        }
        if (command == "render") {
            if (const std::optional<int> code = help_asked(render_help, args)) return *code;
#ifdef DUALFORM_HAS_RENDER
            return run_render(args);
#else
            return bad_input(
                "render: this dualform was built without the Vulkan renderer "
                "(configure with -DDUALFORM_BUILD_RENDER=ON)");
#endif
        }
        if (command == "help" || command == "--help" || command == "-h") {
            std::fputs(help_text().c_str(), stdout);
            return exit_ok;
        }
        return bad_input("unknown command '" + std::string(command) + "' (try 'dualform help')");
    } catch (const std::exception& e) {
        std::fprintf(stderr, "error: %s\n", e.what());
        return exit_failed;
    }
}
