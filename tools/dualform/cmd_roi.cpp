#include <cstdio>
#include <string>

#include "dualform/api_edit.hpp"
#include "dualform/commands.hpp"
#include "dualform/file_output.hpp"
#include "dualform/scenario.hpp"
#include "dualform/usage.hpp"
#include "json/json_writer.hpp"

namespace dfm::cli {

int run_roi(std::span<const std::string_view> args) {
    std::string scenario_path, out_path;
    for (std::size_t i = 0; i < args.size(); ++i) {
        const std::string_view a = args[i];
        if (a == "--out") {
            if (i + 1 >= args.size()) return bad_input("--out needs a path");
            out_path = std::string(args[++i]);
        } else if (a.starts_with("--") || !scenario_path.empty()) {
            return bad_input(std::string("unexpected argument '") + std::string(a) + "'\n" +
                             usage(roi_help));
        } else {
            scenario_path = std::string(a);
        }
    }
    if (scenario_path.empty() || out_path.empty()) return bad_input(usage(roi_help));

    Scenario scenario;
    if (ToolStatus s = load_scenario(scenario_path, scenario); !s) return bad_input(s.message());
    ScenarioMesh mesh;
    if (ToolStatus s = open_scenario_mesh(scenario, mesh); !s) return bad_input(s.message());
    ScenarioRoi roi;
    if (ToolStatus s = select_roi(scenario.roi, mesh, roi); !s) {
        return bad_input(scenario_path + ": " + s.message());
    }
    if (ToolStatus s = write_index_lines(out_path, roi.vertices); !s) return work_failure(s);

    json::JsonWriter j;
    j.begin_object().field("n_roi", roi.vertices.size());
    if (roi.diagnosis) {
        j.field("loops", roi.diagnosis->loops);
        j.field("bounded_by_last_loop", roi.diagnosis->bounded_by_last_loop);
        j.field("suspect", roi.diagnosis->suspect);
    }
    j.end_object();
    std::printf("%s\n", j.str().c_str());
    return exit_ok;
}

}  // namespace dfm::cli
