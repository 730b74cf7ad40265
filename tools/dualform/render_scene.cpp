#include "dualform/render_scene.hpp"

#include "dualform/edit_chain.hpp"
#include "dualform/mesh_input.hpp"

namespace dfm::cli {

Status load_render_scene(std::span<const std::string> inputs, RenderScene& out) {
    out = RenderScene{};
    if (inputs.empty()) return Status(Errc::invalid_argument, "nothing to render");
    bool scenarios = true;
    for (const std::string& input : inputs) scenarios = scenarios && input.ends_with(".json");
    if (!scenarios) {
        if (inputs.size() > 1) {
            return Status(Errc::invalid_argument,
                          "give one mesh, or one or more scenarios (.json)");
        }
        mesh::LoadReport report;
        return load_mesh_input(inputs.front(), out.rest, report);
    }
    EditChain chain;
    if (Status s = run_edit_chain(inputs, chain); !s) return s;
    out.rest = std::move(chain.rest);
    out.deformed = std::move(chain.deformed);
    out.marks = std::move(chain.marks);
    return Status::ok();
}

}  // namespace dfm::cli
