#pragma once

#include <deque>
#include <string>
#include <vector>

#include "editor.hpp"
#include "imgui_layer.hpp"
#include "input_router.hpp"
#include "input_script.hpp"
#include "panel.hpp"

namespace viewer {

// Replays a script as input: each event becomes pointer and key steps, one
// per frame, that go through the InputRouter as GLFW's callbacks would, the
// pointer ImGui sees being the script's (ScriptedPointer). A press comes a
// frame after the pointer reached its place, so the panel knows whether it
// is under it, as it does for a real mouse.
class ScriptPlayer {
public:
    ScriptPlayer(std::vector<ScriptEvent> events, InputRouter& router, Editor& editor, Panel& panel)
        : events_(std::move(events)), router_(router), editor_(editor), panel_(panel) {}

    bool active() const { return next_ < events_.size() || !steps_.empty(); }
    const ScriptedPointer& pointer() const { return pointer_; }

    // One frame's worth; false when an event failed (a file that could not
    // be written, a panel control that is not there).
    bool step(double now_ms);

    // A screenshot the script asked for: the path the next presented frame
    // (panel included) goes to; empty when none.
    const std::string& pending_screenshot() const { return screenshot_; }
    void screenshot_taken() { screenshot_.clear(); }

private:
    struct Step {
        // to_control: the pointer goes to a panel control's centre once the
        // control has stood still for a frame (the panel's layout may change
        // with the event before).
        enum class Kind { move, to_control, press, release, key_down, key_up, text };
        Kind kind = Kind::move;
        double x = 0, y = 0;
        int code = 0, mods = 0;
        std::string text;  // typed text; the control's name for to_control
        ControlRect seen{};
        bool has_seen = false;
        int line = 0;
    };

    static Step make(Step::Kind kind, double x = 0, double y = 0);
    bool run(const ScriptEvent& e);
    void click_at(double x, double y);
    void click_control(const ScriptEvent& e, const std::string& name);
    // False while the step must run again next frame; `failed` when it cannot.
    bool run_step(Step& s, bool& failed);

    std::vector<ScriptEvent> events_;
    InputRouter& router_;
    Editor& editor_;
    Panel& panel_;
    std::size_t next_ = 0;
    std::deque<Step> steps_;
    ScriptedPointer pointer_;
    bool waiting_ = false;
    double wait_started_ = 0, paused_ms_ = 0;
    std::string screenshot_;
};

}  // namespace viewer
