#include "dualform/render_scene.hpp"

#include "dualform/c_api.hpp"

namespace dfm::cli {

namespace {

ToolStatus load_plain_mesh(const std::string& spec, MeshArrays& out) {
    ContextPtr context;
    if (ToolStatus s = create_context(context); !s) return s;
    dfm_mesh* loaded = nullptr;
    if (ToolStatus s = api_status(dfm_mesh_load(context.get(), spec.c_str(), &loaded)); !s)
        return s;
    const MeshPtr mesh(loaded);
    dfm_mesh_info info = {};
    if (ToolStatus s = api_status(dfm_mesh_get_info(mesh.get(), &info)); !s) return s;
    out.positions.resize(info.vertex_count);
    dfm_vec3_output positions = {};
    positions.data = out.positions.data();
    positions.count = info.vertex_count;
    positions.type = DFM_SCALAR_FLOAT64;
    if (ToolStatus s = api_status(dfm_mesh_read_positions(mesh.get(), &positions)); !s) return s;
    out.indices.resize(3 * info.triangle_count);
    return api_status(dfm_mesh_read_indices(mesh.get(), out.indices.data(), out.indices.size()));
}

}  // namespace

ToolStatus load_render_scene(std::span<const std::string> inputs, RenderScene& out) {
    out = RenderScene{};
    if (inputs.empty()) return ToolStatus(DFM_ERROR_INVALID_ARGUMENT, "nothing to render");
    bool scenarios = true;
    for (const std::string& input : inputs) scenarios = scenarios && input.ends_with(".json");
    if (!scenarios) {
        if (inputs.size() > 1) {
            return ToolStatus(DFM_ERROR_INVALID_ARGUMENT,
                              "give one mesh, or one or more scenarios (.json)");
        }
        return load_plain_mesh(inputs.front(), out.rest);
    }
    EditChain chain;
    if (ToolStatus s = run_edit_chain(inputs, chain); !s) return s;
    out.rest = std::move(chain.rest);
    out.deformed = std::move(chain.deformed);
    out.marks = std::move(chain.marks);
    return ToolStatus::ok();
}

}  // namespace dfm::cli
