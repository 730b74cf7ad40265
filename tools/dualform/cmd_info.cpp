#include <cstdio>
#include <string>

#include "dualform/c_api.hpp"
#include "dualform/commands.hpp"
#include "dualform/usage.hpp"
#include "json/json_writer.hpp"

namespace dfm::cli {

int run_info(std::span<const std::string_view> args) {
    if (args.size() != 1) return bad_input(usage(info_help));
    const std::string spec(args[0]);
    ContextPtr context;
    if (ToolStatus s = create_context(context); !s) return bad_input(s.message());
    dfm_load_report loaded = {};
    dfm_mesh* handle = nullptr;
    if (ToolStatus s =
            api_status(dfm_mesh_load_with_report(context.get(), spec.c_str(), &loaded, &handle));
        !s) {
        return bad_input(s.message());
    }
    const MeshPtr mesh(handle);
    dfm_mesh_info info = {};
    dfm_mesh_summary summary = {};
    if (ToolStatus s = api_status(dfm_mesh_get_info(mesh.get(), &info)); !s) {
        return bad_input(s.message());
    }
    if (ToolStatus s = api_status(dfm_mesh_get_summary(mesh.get(), &summary)); !s) {
        return bad_input(s.message());
    }

    json::JsonWriter json;
    json.begin_object();
    json.field("mesh", spec);
    json.field("vertices", info.vertex_count);
    json.field("surface_vertices", info.surface_vertex_count);
    json.field("faces", info.triangle_count);
    json.field("edges", summary.edges);
    json.field("boundary_edges", summary.boundary_edges);
    json.field("non_manifold_edges", summary.non_manifold_edges);
    json.field("inconsistent_edges", summary.inconsistent_edges);
    json.field("components", summary.components);
    json.field("isolated_vertices", summary.isolated_vertices);
    json.field("closed", summary.closed);
    json.field("degenerate_faces", summary.degenerate_triangles);
    json.field("dropped_faces", loaded.dropped_faces);
    json.field("polygons", loaded.polygons);
    json.field("triangulated_polygons", loaded.triangulated_polygons);
    json.key("bbox_min").numbers(info.bounds_min, 3);
    json.key("bbox_max").numbers(info.bounds_max, 3);
    json.field("bbox_diagonal", info.diagonal);
    json.end_object();
    std::printf("%s\n", json.str().c_str());
    return exit_ok;
}

}  // namespace dfm::cli
