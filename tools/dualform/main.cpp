#include <cstdio>
#include <string>
#include <vector>

#include "dualform/commands.hpp"

namespace dfm::cli {

int bad_input(std::string_view message) {
    std::fprintf(stderr, "error: %.*s\n", static_cast<int>(message.size()), message.data());
    return exit_bad_input;
}

namespace {

constexpr const char* help_text =
    "dualform — real-time ROI mesh deformation with the dual Laplacian\n"
    "\n"
    "usage: dualform COMMAND [ARGS]\n"
    "\n"
    "commands:\n"
    "  info PATH|model:NAME   print one JSON object describing the mesh\n"
    "  convert IN OUT         write IN in the format OUT's extension names (.off .obj .ply)\n"
    "  deform SCENARIO --out MESH [--report JSON] [--roi-out TXT] [--strict]\n"
    "                         replay an edit scenario; prints its report as JSON\n"
    "  bench SCENARIO... [--repeat N] [--json FILE]\n"
    "                         time set-up, solve and a 60-frame drag; JSON out\n"
    "  pick MESH --camera JSON --pixel X,Y [--bench N]\n"
    "                         pick the surface through a camera pixel; prints the hit as JSON\n"
    "                         (JSON: a camera object inline, or a file holding one;\n"
    "                         --bench N times N picks instead)\n"
    "  roi SCENARIO --out TXT write the scenario's ROI, one vertex a line; prints its size\n"
    "                         and, for Water-Filling, the cut-loop diagnosis as JSON\n"
    "  render (SCENARIO|MESH) --png OUT [--camera JSON] [--width W --height H]\n"
    "         [--before-after] [--wireframe] [--flat] [--samples 1|2|4] [--bench N]\n"
    "                         draw a mesh, or a scenario's result with its ROI red and\n"
    "                         handles green, into a PNG (Vulkan, headless);\n"
    "                         --before-after: rest and deformed side by side;\n"
    "                         --samples: MSAA at most (default 4, where the device has it);\n"
    "                         --bench N: time N frames with the position upload (JSON out)\n"
    "  help                   print this text\n"
    "\n"
    "exit codes: 0 success, 2 bad input (error: ... on stderr), 1 the work failed\n"
    "meshes: OFF, OBJ or PLY files; model:NAME is NAME.off in the model cache\n"
    "        ($DUALFORM_MODELS, default ~/.cache/dualform/models; tools/fetch-models fills it)\n";

}  // namespace

}  // namespace dfm::cli

int main(int argc, char** argv) {
    using namespace dfm::cli;
    try {
        if (argc < 2) {
            std::fputs(help_text, stderr);
            return exit_bad_input;
        }
        const std::string_view command = argv[1];
        const std::vector<std::string_view> args(argv + 2, argv + argc);
        if (command == "info") return run_info(args);
        if (command == "convert") return run_convert(args);
        if (command == "deform") return run_deform(args);
        if (command == "bench") return run_bench(args);
        if (command == "pick") return run_pick(args);
        if (command == "roi") return run_roi(args);
        if (command == "render") {
#ifdef DUALFORM_HAS_RENDER
            return run_render(args);
#else
            return bad_input(
                "render: this dualform was built without the Vulkan renderer "
                "(configure with -DDUALFORM_BUILD_RENDER=ON)");
#endif
        }
        if (command == "help" || command == "--help" || command == "-h") {
            std::fputs(help_text, stdout);
            return exit_ok;
        }
        return bad_input("unknown command '" + std::string(command) + "' (try 'dualform help')");
    } catch (const std::exception& e) {
        std::fprintf(stderr, "error: %s\n", e.what());
        return exit_failed;
    }
}
