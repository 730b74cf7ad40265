#pragma once

#include <string>
#include <vector>

namespace viewer {

// One timed input event of a --script file. Each line reads
//   TIME_MS EVENT ARGS...        (# starts a comment)
// with EVENT one of
//   click X Y                    left button press and release at pixel (X, Y)
//   drag X0 Y0 X1 Y1 FRAMES [shift]   left-drag over FRAMES frames
//   key NAME                     a key press: a letter, digit, Enter, Escape,
//                                Backspace, or ctrl+LETTER
//   wait                         hold the script until the edit's newest
//                                targets have their finished result
//   screenshot FILE.png          the window's picture, as the renderer draws it
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
