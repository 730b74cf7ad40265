#pragma once

#include <span>
#include <string>
#include <string_view>

// What each subcommand takes and does: `dualform COMMAND --help` prints it
// (exit 0), a bad argument prints it after the error (exit 2), and
// `dualform help` lists every command's.
namespace dfm::cli {

struct CommandHelp {
    std::string_view name;
    std::string_view synopsis;  // the arguments; continuation lines start with a newline
    std::string_view summary;   // what it does, one or more lines
};

inline constexpr CommandHelp info_help{
    "info", "PATH|model:NAME",
    "print one JSON object describing the mesh: counts, topology, bounds"};

inline constexpr CommandHelp convert_help{
    "convert",
    "IN OUT [--ply ascii|binary_little_endian|binary_big_endian] [--ply-float]\n"
    "[--obj-normals]",
    "write IN in the format OUT's extension names (.off .obj .ply .gltf\n"
    ".glb, or .fbx from an FBX IN); --ply-float: PLY with float coordinates;\n"
    "--obj-normals: OBJ with vertex normals"};

inline constexpr CommandHelp deform_help{
    "deform",
    "SCENARIO --out MESH [--report JSON] [--roi-out TXT] [--strict]\n"
    "[--hard-handles] [--method fitted_rotations|paper] [--morph-target NAME]",
    "replay an edit scenario (docs/scenarios.md) and write the deformed\n"
    "mesh; prints its report as JSON. --roi-out: the ROI, one vertex a line;\n"
    "--strict: exit 1 unless the solve converged; --hard-handles: handles\n"
    "exactly on their targets; --method: the outer iteration (docs/method.md);\n"
    "--morph-target NAME: for a glTF or FBX mesh, keep the asset's positions\n"
    "and add the edit as the morph target (FBX: blend shape channel) NAME\n"
    "(docs/gltf.md, docs/fbx.md)"};

inline constexpr CommandHelp bench_help{
    "bench",
    "SCENARIO... [--repeat N] [--json FILE]\n"
    "[--preconditioner cholesky|incomplete_cholesky|jacobi] [--workers N]\n"
    "[--no-prediction] [--tolerance T]",
    "time set-up, solve and a 60-frame drag of each scenario; JSON out"};

inline constexpr CommandHelp pick_help{
    "pick", "MESH --camera JSON --pixel X,Y [--bench N]",
    "pick the surface through a camera pixel; prints the hit as JSON. JSON: a\n"
    "camera object inline (starting with '{') or a file holding one; --bench N\n"
    "times N picks instead"};

inline constexpr CommandHelp roi_help{
    "roi", "SCENARIO --out TXT",
    "write the scenario's ROI, one vertex a line; prints its size and, for\n"
    "Water-Filling, the cut-loop diagnosis as JSON"};

inline constexpr CommandHelp render_help{
    "render",
    "(SCENARIO...|MESH) --png OUT [--camera JSON] [--width W --height H]\n"
    "[--before-after] [--wireframe] [--flat] [--samples 1|2|4] [--bench N]",
    "draw a mesh, or a scenario's result with its ROI red and handles green,\n"
    "into a PNG (Vulkan, headless); several scenarios: successive edits of one\n"
    "mesh, each baked before the next; --before-after: rest and deformed side\n"
    "by side; --samples: MSAA at most (default 4, where the device has it);\n"
    "--bench N: time N frames with the position upload (JSON out)"};

inline constexpr CommandHelp help_help{"help", "", "print this text"};

inline constexpr CommandHelp all_commands[] = {info_help, convert_help, deform_help, bench_help,
                                               pick_help, roi_help,     render_help, help_help};

// "usage: dualform NAME SYNOPSIS" and the summary, indented.
std::string usage(const CommandHelp& command);

// `dualform help`: every command, the exit codes and the mesh formats.
std::string help_text();

// Whether the arguments after a command ask for its usage (--help or -h).
bool asks_for_help(std::span<const std::string_view> args);

}  // namespace dfm::cli
