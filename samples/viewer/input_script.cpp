#include "input_script.hpp"

#include <fstream>
#include <sstream>

namespace viewer {

namespace {

// Each event's argument count: the fixed ones, then how many may follow.
struct Arity {
    std::size_t required;
    std::size_t optional;
};

bool arity_of(const std::string& name, Arity& out) {
    static const std::pair<const char*, Arity> table[] = {
        {"click", {2, 0}},         {"drag", {5, 1}},        {"key", {1, 0}},
        {"wait", {0, 0}},          {"quit", {0, 0}},        {"screenshot", {1, 0}},
        {"save-scenario", {1, 0}}, {"save-camera", {1, 0}}, {"screenshot-mesh", {1, 0}},
        {"panel-click", {1, 0}},   {"panel-type", {2, 0}},
    };
    for (const auto& [event, arity] : table) {
        if (name == event) {
            out = arity;
            return true;
        }
    }
    return false;
}

}  // namespace

bool load_script(const std::string& path, std::vector<ScriptEvent>& out, std::string& error) {
    out.clear();
    std::ifstream in(path);
    if (!in) {
        error = path + ": cannot open the script";
        return false;
    }
    std::string text;
    int line_number = 0;
    double previous = 0.0;
    while (std::getline(in, text)) {
        ++line_number;
        const std::size_t hash = text.find('#');
        if (hash != std::string::npos) text.resize(hash);
        std::istringstream words(text);
        ScriptEvent event;
        event.line = line_number;
        std::string time;
        if (!(words >> time)) continue;
        const std::string where = path + ":" + std::to_string(line_number) + ": ";
        try {
            std::size_t used = 0;
            event.time_ms = std::stod(time, &used);
            if (used != time.size() || event.time_ms < previous) throw std::invalid_argument(time);
        } catch (const std::exception&) {
            error = where + "the time '" + time + "' is not a number of milliseconds at or after " +
                    std::to_string(previous);
            return false;
        }
        previous = event.time_ms;
        Arity arity{};
        if (!(words >> event.name) || !arity_of(event.name, arity)) {
            error = where + "unknown event '" + event.name + "'";
            return false;
        }
        for (std::string word; words >> word;) event.args.push_back(word);
        if (event.args.size() < arity.required ||
            event.args.size() > arity.required + arity.optional) {
            error = where + event.name + " takes " + std::to_string(arity.required) +
                    (arity.optional > 0 ? " or " + std::to_string(arity.required + arity.optional)
                                        : std::string()) +
                    " arguments";
            return false;
        }
        out.push_back(std::move(event));
    }
    return true;
}

}  // namespace viewer
