#include "dualform/render_scene.hpp"

#include <memory>

#include "deform/deform_session.hpp"
#include "dualform/edit_setup.hpp"
#include "dualform/mesh_input.hpp"
#include "dualform/scenario.hpp"

namespace dfm::cli {

namespace {

constexpr std::uint8_t mark_roi = 1;
constexpr std::uint8_t mark_handle = 2;
constexpr std::uint8_t mark_fixed = 3;

Status load_scenario_scene(const std::string& path, RenderScene& out) {
    Scenario scenario;
    if (Status s = load_scenario(path, scenario); !s) return s;
    deform::MeshModel model;
    if (Status s = load_scenario_model(scenario, model); !s) return s;
    EditSetup edit;
    if (Status s = resolve_edit(scenario, model, edit); !s) {
        return Status(s.code(), path + ": " + s.message());
    }
    std::unique_ptr<deform::DeformSession> session;
    if (Status s = deform::DeformSession::create(model, edit.roi, edit.handle_groups, edit.settings,
                                                 session);
        !s) {
        return Status(s.code(), path + ": " + s.message());
    }
    if (Status s = session->set_targets(edit.targets); !s) return s;
    deform::SolveReport solved;
    if (Status s = session->solve(solved); !s) return s;

    out.marks.assign(model.mesh.vertex_count(), 0);
    for (std::uint32_t v : edit.roi) out.marks[v] = mark_roi;
    for (std::size_t g = 0; g < edit.handle_groups.size(); ++g) {
        const HandleSpec& spec = scenario.handles[g];
        const bool anchor = !spec.translate && !spec.rotate && spec.targets.empty();
        for (std::uint32_t v : edit.handle_groups[g]) {
            out.marks[v] = anchor ? mark_fixed : mark_handle;
        }
    }
    out.deformed.assign(session->positions().begin(), session->positions().end());
    out.rest = std::move(model.mesh);
    return Status::ok();
}

}  // namespace

Status load_render_scene(const std::string& input, RenderScene& out) {
    if (input.ends_with(".json")) return load_scenario_scene(input, out);
    mesh::LoadReport report;
    return load_mesh_input(input, out.rest, report);
}

}  // namespace dfm::cli
