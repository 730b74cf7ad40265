#include "key_help.hpp"

#include <algorithm>

namespace viewer {

namespace {

constexpr KeyHelp mouse[] = {
    {"left click", "1st: the limb's tip; 2nd: where the region ends (Water-Filling)"},
    {"left click (then)", "add a handle: a ball of ROI vertices around the click"},
    {"left drag", "move the handle group nearest the pointer in the view plane"},
    {"shift + left drag", "rotate it about the view axis"},
    {"right / middle drag", "orbit / pan"},
    {"wheel", "zoom"},
};

constexpr KeyHelp keys[] = {
    {"Enter", "keep a region marked SUSPECT"},
    {"Escape", "cancel the selection"},
    {"B", "bake the edit into the mesh"},
    {"Ctrl+Z / Ctrl+Y", "undo / redo a bake"},
    {"R or Backspace", "reset the handles"},
    {"[ ]", "smaller / larger handle balls"},
    {"W / F", "wireframe / flat shading"},
    {"S", "save the mesh (baking an unbaked edit) to the panel's path"},
    {"E", "save the edit as a scenario (viewer_edit.json)"},
    {"H or F1", "show / hide this help"},
    {"Q", "quit"},
};

}  // namespace

std::span<const KeyHelp> mouse_help() {
    return mouse;
}

std::span<const KeyHelp> key_help() {
    return keys;
}

std::string usage_text() {
    std::string text =
        "usage: viewer [MESH] [--script FILE] [--width W] [--height H] [--out MESH_FILE]\n"
        "\n"
        "MESH: a mesh file dfm_mesh_load reads (.off, .obj, .ply), or model:NAME\n"
        "(default model:cow). --out: the path the panel's Save starts with\n"
        "(default viewer_mesh.off). The panel on the left shows the region, the\n"
        "handles, the solver's settings and figures, bake / undo / redo and\n"
        "open / save.\n";
    const auto table = [&](const char* title, std::span<const KeyHelp> rows) {
        text += "\n";
        text += title;
        text += "\n";
        for (const KeyHelp& row : rows) {
            std::string input = "  ";
            input += row.input;
            input.resize(std::max<std::size_t>(input.size() + 1, 24), ' ');
            text += input + row.does + "\n";
        }
    };
    table("mouse (outside the panel)", mouse_help());
    table("keys (while no panel field has the keyboard)", key_help());
    text += "\n--script FILE replays timed input (see README.md) through the same code.\n";
    return text;
}

}  // namespace viewer
