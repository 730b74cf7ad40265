#include <cstdio>
#include <string>

#include "dualform/c_api.hpp"
#include "dualform/commands.hpp"
#include "dualform/usage.hpp"
#include "json/json_writer.hpp"

namespace dfm::cli {

namespace {

// What poses the mesh, where something does: its skin (joints and their
// parents, influences per vertex), animations and morph targets.
ToolStatus write_skin(json::JsonWriter& json, const dfm_mesh* mesh) {
    dfm_skin_info skin = {};
    if (ToolStatus s = api_status(dfm_mesh_get_skin_info(mesh, &skin)); !s) return s;
    if (skin.joint_count == 0 && skin.morph_target_count == 0) return ToolStatus::ok();
    json.key("skin").begin_object();
    json.field("joints", skin.joint_count);
    json.field("max_influences", skin.max_influences);
    json.field("skinned_vertices", skin.skinned_vertex_count);
    json.key("joint_names").begin_array();
    for (std::uint32_t j = 0; j < skin.joint_count; ++j) {
        dfm_joint_info joint = {};
        if (ToolStatus s = api_status(dfm_mesh_get_joint_info(mesh, j, &joint)); !s) return s;
        json.value(joint.name);
    }
    json.end_array();
    json.end_object();
    json.key("animations").begin_array();
    for (std::uint32_t a = 0; a < skin.animation_count; ++a) {
        dfm_animation_info animation = {};
        if (ToolStatus s = api_status(dfm_mesh_get_animation_info(mesh, a, &animation)); !s) {
            return s;
        }
        json.begin_object();
        json.field("name", animation.name);
        json.field("start", animation.start);
        json.field("end", animation.end);
        json.field("duration", animation.end - animation.start);
        json.key("channels").begin_object();
        json.field("translation", animation.translation_channels);
        json.field("rotation", animation.rotation_channels);
        json.field("scale", animation.scale_channels);
        json.field("weights", animation.weight_channels);
        json.end_object();
        json.end_object();
    }
    json.end_array();
    json.key("morph_targets").begin_array();
    for (std::uint32_t t = 0; t < skin.morph_target_count; ++t) {
        dfm_morph_target_info target = {};
        if (ToolStatus s = api_status(dfm_mesh_get_morph_target_info(mesh, t, &target)); !s) {
            return s;
        }
        json.begin_object();
        json.field("name", target.name);
        json.field("default_weight", target.default_weight);
        json.field("vertices", target.vertex_count);
        json.end_object();
    }
    json.end_array();
    return ToolStatus::ok();
}

}  // namespace

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
    if (ToolStatus s = write_skin(json, mesh.get()); !s) return bad_input(s.message());
    json.end_object();
    std::printf("%s\n", json.str().c_str());
    return exit_ok;
}

}  // namespace dfm::cli
