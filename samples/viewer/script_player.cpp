#include "script_player.hpp"

#include <GLFW/glfw3.h>

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <cstdlib>

namespace viewer {

ScriptPlayer::Step ScriptPlayer::make(Step::Kind kind, double x, double y) {
    Step s;
    s.kind = kind;
    s.x = x;
    s.y = y;
    return s;
}

bool ScriptPlayer::run_step(Step& s, bool& failed) {
    switch (s.kind) {
        case Step::Kind::to_control: {
            ControlRect r;
            if (!panel_.find_control(s.text, r)) {
                std::fprintf(stderr,
                             "viewer: script line %d: the panel shows no control '%s' now\n",
                             s.line, s.text.c_str());
                failed = true;
                return true;
            }
            const bool still = s.has_seen && r.x0 == s.seen.x0 && r.y0 == s.seen.y0 &&
                               r.x1 == s.seen.x1 && r.y1 == s.seen.y1;
            s.seen = r;
            s.has_seen = true;
            if (!still) return false;
            pointer_.x = 0.5 * (r.x0 + r.x1);
            pointer_.y = 0.5 * (r.y0 + r.y1);
            router_.cursor(pointer_.x, pointer_.y);
            break;
        }
        case Step::Kind::move:
            pointer_.x = s.x;
            pointer_.y = s.y;
            router_.cursor(s.x, s.y);
            break;
        case Step::Kind::press:
            pointer_.down[0] = true;
            router_.button(GLFW_MOUSE_BUTTON_LEFT, GLFW_PRESS, s.mods, pointer_.x, pointer_.y);
            break;
        case Step::Kind::release:
            pointer_.down[0] = false;
            router_.button(GLFW_MOUSE_BUTTON_LEFT, GLFW_RELEASE, s.mods, pointer_.x, pointer_.y);
            break;
        case Step::Kind::key_down: router_.key(s.code, GLFW_PRESS, s.mods); break;
        case Step::Kind::key_up: router_.key(s.code, GLFW_RELEASE, s.mods); break;
        case Step::Kind::text:
            // As a keyboard types: a letter's key goes down and up around its
            // character, so a field that has the keyboard must keep the
            // letter from being a shortcut.
            for (const char c : s.text) {
                const bool letter = std::isalpha(static_cast<unsigned char>(c)) != 0;
                const int key = GLFW_KEY_A + (std::tolower(static_cast<unsigned char>(c)) - 'a');
                if (letter) router_.key(key, GLFW_PRESS, 0);
                router_.character(static_cast<unsigned char>(c));
                if (letter) router_.key(key, GLFW_RELEASE, 0);
            }
            break;
    }
    return true;
}

void ScriptPlayer::click_at(double x, double y) {
    steps_.push_back(make(Step::Kind::move, x, y));
    steps_.push_back(make(Step::Kind::press));
    steps_.push_back(make(Step::Kind::release));
}

void ScriptPlayer::click_control(const ScriptEvent& e, const std::string& name) {
    Step to = make(Step::Kind::to_control);
    to.text = name;
    to.line = e.line;
    steps_.push_back(to);
    steps_.push_back(make(Step::Kind::press));
    steps_.push_back(make(Step::Kind::release));
}

bool ScriptPlayer::run(const ScriptEvent& e) {
    const auto number = [&](std::size_t i) { return std::atof(e.args[i].c_str()); };
    if (e.name == "click") {
        click_at(number(0), number(1));
    } else if (e.name == "drag") {
        const int frames = std::max(1, std::atoi(e.args[4].c_str()));
        const int mods = e.args.size() > 5 && e.args[5] == "shift" ? GLFW_MOD_SHIFT : 0;
        steps_.push_back(make(Step::Kind::move, number(0), number(1)));
        Step press = make(Step::Kind::press);
        press.mods = mods;
        steps_.push_back(press);
        for (int i = 1; i <= frames; ++i) {
            const double t = double(i) / frames;
            steps_.push_back(make(Step::Kind::move, number(0) + t * (number(2) - number(0)),
                                  number(1) + t * (number(3) - number(1))));
        }
        steps_.push_back(make(Step::Kind::release));
    } else if (e.name == "key") {
        Step down = make(Step::Kind::key_down);
        if (!parse_key_name(e.args[0], down.code, down.mods)) {
            std::fprintf(stderr, "viewer: script line %d: unknown key '%s'\n", e.line,
                         e.args[0].c_str());
            return false;
        }
        Step up = down;
        up.kind = Step::Kind::key_up;
        steps_.push_back(down);
        steps_.push_back(up);
    } else if (e.name == "panel-click") {
        click_control(e, e.args[0]);
    } else if (e.name == "panel-type") {
        // Click into the field (it selects all), type, Enter: as a user would.
        click_control(e, e.args[0]);
        Step text = make(Step::Kind::text);
        text.text = e.args[1];
        steps_.push_back(text);
        Step down = make(Step::Kind::key_down);
        down.code = GLFW_KEY_ENTER;
        Step up = down;
        up.kind = Step::Kind::key_up;
        steps_.push_back(down);
        steps_.push_back(up);
    } else if (e.name == "wait") {
        waiting_ = true;
    } else if (e.name == "screenshot") {
        screenshot_ = e.args[0];
    } else if (e.name == "screenshot-mesh") {
        return editor_.write_screenshot(e.args[0]);
    } else if (e.name == "save-scenario") {
        return editor_.save_scenario(e.args[0]);
    } else if (e.name == "save-camera") {
        return editor_.save_camera(e.args[0]);
    } else if (e.name == "quit") {
        editor_.key("q");
    }
    return true;
}

bool ScriptPlayer::step(double now_ms) {
    if (!steps_.empty()) {
        bool failed = false;
        if (run_step(steps_.front(), failed)) steps_.pop_front();
        return !failed;
    }
    if (!screenshot_.empty()) return true;
    if (waiting_) {
        if (!editor_.settled()) return true;
        waiting_ = false;
        paused_ms_ += now_ms - wait_started_;
    }
    // Events wait for the steps of the one before: a click, a drag or typing
    // ends before what follows it starts.
    while (next_ < events_.size() && steps_.empty() && screenshot_.empty() && !waiting_ &&
           events_[next_].time_ms <= now_ms - paused_ms_) {
        const ScriptEvent& e = events_[next_++];
        if (e.name == "wait") wait_started_ = now_ms;
        if (!run(e)) return false;
    }
    return true;
}

}  // namespace viewer
