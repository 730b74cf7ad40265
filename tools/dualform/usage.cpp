#include "dualform/usage.hpp"

#include <algorithm>

namespace dfm::cli {

namespace {

// `text` with every line after the first indented by `indent`.
void append_indented(std::string& out, std::string_view text, std::string_view indent) {
    for (const char c : text) {
        out += c;
        if (c == '\n') out += indent;
    }
}

// NAME SYNOPSIS, then the summary on lines of its own; `synopsis_indent`
// and `summary_indent` start the lines after the first.
void append_command(std::string& out, const CommandHelp& command, std::string_view synopsis_indent,
                    std::string_view summary_indent) {
    out += command.name;
    if (!command.synopsis.empty()) {
        out += ' ';
        append_indented(out, command.synopsis, synopsis_indent);
    }
    out += '\n';
    out += summary_indent;
    append_indented(out, command.summary, summary_indent);
}

}  // namespace

std::string usage(const CommandHelp& command) {
    std::string out = "usage: dualform ";
    append_command(out, command, "       ", "  ");
    return out;
}

std::string help_text() {
    std::string out =
        "dualform — real-time ROI mesh deformation with the dual Laplacian\n"
        "\n"
        "usage: dualform COMMAND [ARGS]   (dualform COMMAND --help: that command's usage)\n"
        "\n"
        "commands:\n";
    for (const CommandHelp& command : all_commands) {
        out += "  ";
        append_command(out, command, "    ", "        ");
        out += '\n';
    }
    out +=
        "\n"
        "exit codes: 0 success, 2 bad input (error: ... on stderr), 1 the work failed\n"
        "meshes: OFF, OBJ, PLY, glTF 2.0 (.gltf, .glb; FILE.glb#mesh=NAME or\n"
        "        #mesh=INDEX for one mesh of the asset; docs/gltf.md) or FBX 7.x files\n"
        "        (.fbx, binary or ASCII; docs/fbx.md); model:NAME is\n"
        "        NAME.off in the model cache ($DUALFORM_MODELS, default\n"
        "        ~/.cache/dualform/models; tools/fetch-models fills it)\n";
    return out;
}

bool asks_for_help(std::span<const std::string_view> args) {
    return std::ranges::any_of(args, [](std::string_view a) { return a == "--help" || a == "-h"; });
}

}  // namespace dfm::cli
