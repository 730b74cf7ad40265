#include "dualform/edit_chain.hpp"

#include <memory>

#include "deform/deform_session.hpp"
#include "deform/mesh_model.hpp"
#include "dualform/edit_setup.hpp"
#include "dualform/scenario.hpp"

namespace dfm::cli {

namespace {

Status in_chain(const Status& s, const std::string& path, std::size_t index, std::size_t count) {
    std::string where = path;
    if (count > 1) {
        where += " (edit ";
        where += std::to_string(index + 1);
        where += " of ";
        where += std::to_string(count);
        where += ")";
    }
    where += ": ";
    where += s.message();
    return Status(s.code(), where);
}

}  // namespace

Status run_edit_chain(std::span<const std::string> scenario_paths, EditChain& out) {
    out = EditChain{};
    if (scenario_paths.empty()) return Status(Errc::invalid_argument, "no scenario given");
    deform::MeshModel model;
    std::string mesh_spec;
    const std::size_t count = scenario_paths.size();
    for (std::size_t i = 0; i < count; ++i) {
        const std::string& path = scenario_paths[i];
        Scenario scenario;
        if (Status s = load_scenario(path, scenario); !s) return s;
        if (i == 0) {
            if (Status s = load_scenario_model(scenario, model); !s) return s;
            mesh_spec = scenario.mesh;
            out.rest = model.mesh;
            out.marks.assign(model.mesh.vertex_count(), 0);
        } else if (scenario.mesh != mesh_spec || scenario.subdivide != 0) {
            return in_chain(
                Status(Errc::invalid_argument, "edits in a chain must all name \"" + mesh_spec +
                                                   "\" without subdivision; this one names \"" +
                                                   scenario.mesh + "\""),
                path, i, count);
        }
        EditSetup edit;
        if (Status s = resolve_edit(scenario, model, edit); !s) return in_chain(s, path, i, count);
        std::unique_ptr<deform::DeformSession> session;
        if (Status s = deform::DeformSession::create(model, edit.roi, edit.handle_groups,
                                                     edit.settings, session);
            !s) {
            return in_chain(s, path, i, count);
        }
        if (Status s = session->set_targets(edit.targets); !s) return in_chain(s, path, i, count);
        deform::SolveReport solved;
        if (Status s = session->solve(solved); !s) return in_chain(s, path, i, count);
        if (!solved.converged) ++out.unconverged;

        for (std::uint32_t v : edit.roi) out.marks[v] = mark_roi;
        for (std::size_t g = 0; g < edit.handle_groups.size(); ++g) {
            const HandleSpec& spec = scenario.handles[g];
            const bool anchor = !spec.translate && !spec.rotate && spec.targets.empty();
            for (std::uint32_t v : edit.handle_groups[g]) {
                out.marks[v] = anchor ? mark_anchor : mark_handle;
            }
        }
        if (i + 1 == count) {
            out.deformed.assign(session->positions().begin(), session->positions().end());
            break;
        }
        deform::MeshModel baked;
        if (Status s = deform::bake_positions(model, session->positions(), baked); !s) {
            return in_chain(s, path, i, count);
        }
        session.reset();
        model = std::move(baked);
    }
    return Status::ok();
}

}  // namespace dfm::cli
