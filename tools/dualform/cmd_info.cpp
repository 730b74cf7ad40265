#include <cstdio>
#include <string>

#include "dualform/commands.hpp"
#include "dualform/mesh_input.hpp"
#include "json/json_writer.hpp"
#include "mesh/summary.hpp"

namespace dfm::cli {

namespace {

void write_vec3(json::JsonWriter& json, std::string_view key, const glm::dvec3& v) {
    json.key(key).begin_array().value(v.x).value(v.y).value(v.z).end_array();
}

}  // namespace

int run_info(std::span<const std::string_view> args) {
    if (args.size() != 1) return bad_input("usage: dualform info PATH|model:NAME");
    mesh::Mesh m;
    mesh::LoadReport report;
    if (Status s = load_mesh_input(args[0], m, report); !s) return bad_input(s.message());
    const mesh::MeshSummary s = mesh::summarize(m);

    json::JsonWriter json;
    json.begin_object();
    json.key("mesh").value(args[0]);
    json.key("vertices").value(std::uint64_t{s.vertices});
    json.key("faces").value(std::uint64_t{s.faces});
    json.key("edges").value(std::uint64_t{s.edges});
    json.key("boundary_edges").value(std::uint64_t{s.boundary_edges});
    json.key("non_manifold_edges").value(std::uint64_t{s.non_manifold_edges});
    json.key("inconsistent_edges").value(std::uint64_t{s.inconsistent_edges});
    json.key("components").value(std::uint64_t{s.components});
    json.key("isolated_vertices").value(std::uint64_t{s.isolated_vertices});
    json.key("closed").value(s.closed);
    json.key("degenerate_faces").value(std::uint64_t{s.degenerate_faces});
    json.key("dropped_faces").value(std::uint64_t{report.dropped_faces});
    json.key("polygons").value(std::uint64_t{report.polygons});
    json.key("triangulated_polygons").value(std::uint64_t{report.triangulated_polygons});
    write_vec3(json, "bbox_min", s.bounds.min);
    write_vec3(json, "bbox_max", s.bounds.max);
    json.key("bbox_diagonal").value(s.diagonal);
    json.end_object();
    std::printf("%s\n", json.str().c_str());
    return exit_ok;
}

}  // namespace dfm::cli
