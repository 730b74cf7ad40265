#include <cstdio>
#include <fstream>
#include <optional>
#include <string>
#include <vector>

#include "dualform/commands.hpp"
#include "dualform/edit_setup.hpp"
#include "dualform/scenario.hpp"
#include "json/json_writer.hpp"

namespace dfm::cli {

namespace {

constexpr const char* usage = "usage: dualform roi SCENARIO --out TXT";

}  // namespace

int run_roi(std::span<const std::string_view> args) {
    std::string scenario_path, out_path;
    for (std::size_t i = 0; i < args.size(); ++i) {
        const std::string_view a = args[i];
        if (a == "--out") {
            if (i + 1 >= args.size()) return bad_input("--out needs a path");
            out_path = std::string(args[++i]);
        } else if (a.starts_with("--") || !scenario_path.empty()) {
            return bad_input(std::string("unexpected argument '") + std::string(a) + "'\n" + usage);
        } else {
            scenario_path = std::string(a);
        }
    }
    if (scenario_path.empty() || out_path.empty()) return bad_input(usage);

    Scenario scenario;
    if (Status s = load_scenario(scenario_path, scenario); !s) return bad_input(s.message());
    deform::MeshModel model;
    if (Status s = load_scenario_model(scenario, model); !s) return bad_input(s.message());
    std::vector<std::uint32_t> roi;
    std::optional<roi::WaterFillDiagnosis> diagnosis;
    if (Status s = resolve_roi(scenario.roi, model, roi, diagnosis); !s) {
        return bad_input(scenario_path + ": " + s.message());
    }
    std::string text;
    for (std::uint32_t v : roi) {
        text += std::to_string(v);
        text += '\n';
    }
    std::ofstream out(out_path, std::ios::binary | std::ios::trunc);
    out << text;
    out.close();
    if (!out) return bad_input(out_path + ": cannot write");

    json::JsonWriter j;
    j.begin_object().key("n_roi").value(std::uint64_t{roi.size()});
    if (diagnosis) {
        j.key("loops").value(std::uint64_t{diagnosis->loops});
        j.key("bounded_by_last_loop").value(diagnosis->bounded_by_last_loop);
        j.key("suspect").value(diagnosis->suspect);
    }
    j.end_object();
    std::printf("%s\n", j.str().c_str());
    return exit_ok;
}

}  // namespace dfm::cli
