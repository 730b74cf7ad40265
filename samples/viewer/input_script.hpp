#pragma once

#include <string>
#include <vector>

namespace viewer {

// One timed input event of a --script file; input events go through the
// panel first, as a user's would (script_player.hpp). Each line reads
//   TIME_MS EVENT ARGS...        (# starts a comment)
// with EVENT one of
//   click X Y                    left button press and release at pixel (X, Y)
//   drag X0 Y0 X1 Y1 FRAMES [shift]   left-drag over FRAMES frames
//   key NAME                     a key press and release: a letter, enter,
//                                escape, backspace, [, ], f1, or ctrl+LETTER
//   panel-click CONTROL          a click at the centre of a panel control
//                                (its script name: bake, undo, save, ...)
//   panel-type CONTROL TEXT      a click into a panel field, TEXT typed (each
//                                letter's key pressed and released with it), Enter
//   wait                         hold the script until the edit's newest
//                                targets have their finished result
//   screenshot FILE.png          the window's picture as presented, panel included
//   screenshot-mesh FILE.png     the mesh alone, drawn offscreen at the window's size
//   save-scenario FILE.json      the edit so far, as a scenario file
//   save-camera FILE.json        the view, as a scenario camera
//   quit
struct ScriptEvent {
    double time_ms = 0.0;
    std::string name;
    std::vector<std::string> args;
    int line = 0;
};

// Reads a script; false with "FILE:LINE: what" in `error` on a bad line.
bool load_script(const std::string& path, std::vector<ScriptEvent>& out, std::string& error);

}  // namespace viewer
