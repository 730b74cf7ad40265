#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <optional>
#include <string>
#include <type_traits>

#include "c_boundary.hpp"
#include "host_numbering.hpp"
#include "mesh/load.hpp"
#include "mesh/model_cache.hpp"
#include "mesh/normals.hpp"
#include "mesh/skin_pose.hpp"
#include "mesh/skin_weld.hpp"
#include "mesh/summary.hpp"
#include "mesh/write.hpp"
#include "objects.hpp"
#include "shared_calls.hpp"
#include "skin_input.hpp"
#include "vec3_arrays.hpp"

using namespace dfm;
using namespace dfm::sdk;

namespace dfm::sdk {

dfm_result make_mesh_handle(const ContextState& context,
                            const std::shared_ptr<const ContextState>& shared, mesh::Mesh mesh,
                            dfm_mesh** out, mesh::HostMesh host) {
    auto model =
        std::allocate_shared<deform::MeshModel>(HostAllocator<deform::MeshModel>(context.allocator),
                                                deform::build_mesh_model(std::move(mesh)));
    auto state = std::allocate_shared<MeshState>(HostAllocator<MeshState>(context.allocator),
                                                 shared, std::move(host), std::move(model));
    *out = host_new<MeshObject>(context, std::move(state));
    return DFM_OK;
}

}  // namespace dfm::sdk

namespace {

// dfm_mesh_load and dfm_mesh_load_with_report: the calls' one opening, then
// the load (model:NAME through the context's models folder, the loader's
// warnings logged). `report_out` is written when `with_report`, where NULL
// is refused.
dfm_result load_mesh_call(const char* fn, dfm_context* context, const char* path, bool with_report,
                          dfm_load_report* report_out, dfm_mesh** out) {
    return guarded(fn, [&] {
        if (out == nullptr) return report(fn, DFM_ERROR_INVALID_ARGUMENT, "out is NULL");
        *out = nullptr;
        if (with_report) {
            if (report_out == nullptr) {
                return report(fn, DFM_ERROR_INVALID_ARGUMENT, "report is NULL");
            }
            *report_out = dfm_load_report{};
        }
        ContextObject* c = resolve_context(context);
        if (c == nullptr) return bad_handle(fn, "context", context);
        if (path == nullptr) return report(fn, DFM_ERROR_INVALID_ARGUMENT, "path is NULL");
        std::filesystem::path file;
        const std::string& models = c->state->models_directory;
        if (Status s = mesh::resolve_mesh_spec(path, std::filesystem::current_path(), models, file);
            !s) {
            if (models.empty() && s.code() == Errc::not_found) {
                return report(fn, DFM_ERROR_NOT_FOUND,
                              s.message() + " (set dfm_context_desc.models_directory)");
            }
            return report(fn, s);
        }
        mesh::Mesh m;
        mesh::HostMesh host;
        mesh::LoadReport load_report;
        if (Status s =
                mesh::load_host_mesh(file, m, host, &load_report, c->state->reference_folder);
            !s) {
            return report(fn, s);
        }
        for (const std::string& warning : load_report.warnings) {
            c->state->emit(DFM_LOG_WARNING, DFM_LOG_ID_LOAD_WARNING, warning);
        }
        if (m.vertex_count() == 0 || m.face_count() == 0) {
            return report(fn, DFM_ERROR_PARSE, file.string() + ": the mesh has no triangles");
        }
        if (dfm_result r =
                make_mesh_handle(*c->state, c->state, std::move(m), out, std::move(host));
            r != DFM_OK) {
            return r;
        }
        if (with_report) {
            report_out->polygons = load_report.polygons;
            report_out->triangulated_polygons = load_report.triangulated_polygons;
            report_out->dropped_faces = load_report.dropped_faces;
        }
        return DFM_OK;
    });
}

Status check_triangles(const mesh::Mesh& m) {
    const std::size_t n = m.vertex_count();
    for (std::size_t t = 0; t < m.triangles.size(); ++t) {
        const mesh::Triangle& tri = m.triangles[t];
        for (int c = 0; c < 3; ++c) {
            if (tri[c] >= n) {
                return Status(Errc::out_of_range, "triangle " + std::to_string(t) + " corner " +
                                                      std::to_string(c) + ": vertex " +
                                                      std::to_string(tri[c]) +
                                                      " is out of range (there are " +
                                                      std::to_string(n) + " vertices)");
            }
        }
    }
    return Status::ok();
}

// Drops the triangles that repeat a vertex, as the file loaders do, and
// returns the warning that says so (empty when none was dropped).
std::string drop_repeating_triangles(mesh::Mesh& m) {
    std::size_t first = 0;
    std::size_t dropped = 0;
    std::size_t kept = 0;
    for (std::size_t t = 0; t < m.triangles.size(); ++t) {
        const mesh::Triangle tri = m.triangles[t];
        if (tri[0] == tri[1] || tri[1] == tri[2] || tri[0] == tri[2]) {
            if (dropped++ == 0) first = t;
        } else {
            m.triangles[kept++] = tri;
        }
    }
    m.triangles.resize(kept);
    if (dropped == 0) return {};
    if (dropped == 1) {
        return "dfm_mesh_create: triangle " + std::to_string(first) + " repeats a vertex; dropped";
    }
    return "dfm_mesh_create: " + std::to_string(dropped) +
           " triangles repeat a vertex; dropped (the first: triangle " + std::to_string(first) +
           ")";
}

// The weld a descriptor asks for; the mode read as an integer, since a host
// may pass any value.
Status weld_from(const dfm_mesh_desc& d, const mesh::Mesh& host, mesh::WeldOptions& out) {
    std::underlying_type_t<dfm_weld_mode> mode;
    std::memcpy(&mode, &d.weld, sizeof mode);
    switch (mode) {
        case DFM_WELD_NONE: out.mode = mesh::WeldMode::none; return Status::ok();
        case DFM_WELD_EXACT: out.mode = mesh::WeldMode::exact; return Status::ok();
        case DFM_WELD_TOLERANCE: break;
        default:
            return Status(Errc::invalid_argument,
                          "desc->weld: unknown mode " + std::to_string(mode) +
                              " (DFM_WELD_NONE, _EXACT or _TOLERANCE expected)");
    }
    if (!(d.weld_tolerance > 0.0) || !std::isfinite(d.weld_tolerance)) {
        return Status(Errc::invalid_argument,
                      "desc->weld_tolerance must be positive and finite with DFM_WELD_TOLERANCE");
    }
    out.mode = mesh::WeldMode::tolerance;
    out.tolerance = d.weld_tolerance * mesh::compute_bounds(host.positions).diagonal();
    return Status::ok();
}

}  // namespace

extern "C" DFM_API dfm_result dfm_mesh_create(dfm_context* context, const dfm_mesh_desc* desc,
                                              dfm_mesh** out) {
    constexpr const char* fn = "dfm_mesh_create";
    return guarded(fn, [&] {
        if (out == nullptr) return report(fn, DFM_ERROR_INVALID_ARGUMENT, "out is NULL");
        *out = nullptr;
        ContextObject* c = resolve_context(context);
        if (c == nullptr) return bad_handle(fn, "context", context);
        dfm_mesh_desc d;
        if (dfm_result r = read_descriptor(fn, "desc", desc, d); r != DFM_OK) {
            return r;
        }
        if (std::string e = check_vec3_input(&d.positions, "desc->positions"); !e.empty()) {
            return report(fn, DFM_ERROR_INVALID_ARGUMENT, e);
        }
        if (d.indices == nullptr) {
            return report(fn, DFM_ERROR_INVALID_ARGUMENT, "desc->indices is NULL");
        }
        if (d.positions.count == 0 || d.triangle_count == 0) {
            return report(fn, DFM_ERROR_INVALID_ARGUMENT, "the mesh needs vertices and triangles");
        }
        if (d.positions.count > 0xFFFFFFFEu || d.triangle_count > 0xFFFFFFFEu) {
            return report(fn, DFM_ERROR_OUT_OF_RANGE, "more than 2^32 - 2 vertices or triangles");
        }
        if (d.index_stride != 0 && d.index_stride < 3 * sizeof(std::uint32_t)) {
            return report(fn, DFM_ERROR_INVALID_ARGUMENT,
                          "desc->index_stride " + std::to_string(d.index_stride) +
                              " is smaller than one triangle (12 bytes)");
        }
        mesh::Mesh m;
        m.positions.resize(d.positions.count);
        for (std::size_t i = 0; i < m.positions.size(); ++i) {
            m.positions[i] = read_vec3(d.positions, i);
            if (!std::isfinite(m.positions[i].x) || !std::isfinite(m.positions[i].y) ||
                !std::isfinite(m.positions[i].z)) {
                return report(fn, DFM_ERROR_NUMERICAL,
                              "vertex " + std::to_string(i) + " is not finite");
            }
        }
        const std::size_t stride = d.index_stride != 0 ? d.index_stride : 12;
        m.triangles.resize(d.triangle_count);
        for (std::size_t t = 0; t < m.triangles.size(); ++t) {
            std::memcpy(m.triangles[t].data(),
                        reinterpret_cast<const char*>(d.indices) + t * stride,
                        3 * sizeof(std::uint32_t));
        }
        if (Status s = check_triangles(m); !s) return report(fn, s);
        if (const std::string warning = drop_repeating_triangles(m); !warning.empty()) {
            c->state->emit(DFM_LOG_WARNING, DFM_LOG_ID_LOAD_WARNING, warning);
        }
        if (m.triangles.empty()) {
            return report(fn, DFM_ERROR_INVALID_ARGUMENT,
                          "every triangle repeats a vertex: the mesh has no triangles");
        }
        mesh::WeldOptions weld;
        if (Status s = weld_from(d, m, weld); !s) return report(fn, s);
        mesh::Skin skin;
        if (d.skin.joint_count > 0) {
            if (Status s = read_skin_input(d.skin, m.vertex_count(), skin); !s) {
                return report(fn, s);
            }
        }
        mesh::HostMesh host;
        if (weld.mode == mesh::WeldMode::none) {
            if (skin.vertex_count() > 0)
                host.skin = std::make_shared<const mesh::Skin>(std::move(skin));
            return make_mesh_handle(*c->state, c->state, std::move(m), out, std::move(host));
        }
        mesh::Mesh surface;
        auto welded = std::make_shared<mesh::SeamWeld>();
        mesh::LoadReport weld_report;
        mesh::weld_skinned(m, skin, mesh::WeldBy::skin, weld, fn, surface, *welded, host.skin,
                           weld_report);
        if (surface.face_count() == 0) {
            return report(fn, DFM_ERROR_INVALID_ARGUMENT, "the weld leaves no triangle");
        }
        for (const std::string& warning : weld_report.warnings) {
            c->state->emit(DFM_LOG_WARNING, DFM_LOG_ID_LOAD_WARNING, warning);
        }
        host.weld = std::move(welded);
        return make_mesh_handle(*c->state, c->state, std::move(surface), out, std::move(host));
    });
}

extern "C" DFM_API dfm_result dfm_mesh_load(dfm_context* context, const char* path,
                                            dfm_mesh** out) {
    return load_mesh_call("dfm_mesh_load", context, path, false, nullptr, out);
}

extern "C" DFM_API dfm_result dfm_mesh_load_with_report(dfm_context* context, const char* path,
                                                        dfm_load_report* report_out,
                                                        dfm_mesh** out) {
    return load_mesh_call("dfm_mesh_load_with_report", context, path, true, report_out, out);
}

namespace {

// dfm_mesh_save and dfm_mesh_save_with_options (`options` NULL: the defaults).
dfm_result save_mesh_call(const char* fn, const dfm_mesh* mesh, const char* path,
                          const dfm_save_options* options) {
    return guarded(fn, [&] {
        MeshObject* m = resolve_mesh(mesh);
        if (m == nullptr) return bad_handle(fn, "mesh", mesh);
        if (path == nullptr) return report(fn, DFM_ERROR_INVALID_ARGUMENT, "path is NULL");
        mesh::WriteOptions write;
        if (options != nullptr) {
            dfm_save_options o;
            if (dfm_result r = read_descriptor(fn, "options", options, o); r != DFM_OK) {
                return r;
            }
            // Read as an integer: a host's out-of-range value is not an enum load.
            int encoding = 0;
            static_assert(sizeof(encoding) == sizeof(o.ply_encoding));
            std::memcpy(&encoding, &o.ply_encoding, sizeof encoding);
            switch (encoding) {
                case DFM_PLY_BINARY_LITTLE_ENDIAN:
                    write.ply_encoding = mesh::PlyEncoding::binary_little_endian;
                    break;
                case DFM_PLY_BINARY_BIG_ENDIAN:
                    write.ply_encoding = mesh::PlyEncoding::binary_big_endian;
                    break;
                case DFM_PLY_ASCII: write.ply_encoding = mesh::PlyEncoding::ascii; break;
                default:
                    return report(
                        fn, DFM_ERROR_INVALID_ARGUMENT,
                        "options->ply_encoding " + std::to_string(encoding) + " is unknown");
            }
            write.ply_double = !o.ply_float;
            write.obj_normals = o.obj_normals;
            if (o.morph_target_name != nullptr) write.morph_target = o.morph_target_name;
        }
        const deform::RestPoses& poses = m->state->poses;
        if (!write.morph_target.empty()) {
            if (const std::optional<mesh::SkinPose> pose = poses.skin_pose()) {
                write.morph_target_extras = mesh::pose_record(*poses.skin(), *pose);
            }
        }
        return report(fn, mesh::save_host_mesh(path, poses.bind()->mesh, poses.current()->mesh,
                                               m->state->host, write));
    });
}

}  // namespace

extern "C" DFM_API dfm_result dfm_mesh_save(const dfm_mesh* mesh, const char* path) {
    return save_mesh_call("dfm_mesh_save", mesh, path, nullptr);
}

extern "C" DFM_API dfm_result dfm_mesh_save_with_options(const dfm_mesh* mesh, const char* path,
                                                         const dfm_save_options* options) {
    return save_mesh_call("dfm_mesh_save_with_options", mesh, path, options);
}

extern "C" DFM_API void dfm_mesh_destroy(dfm_mesh* mesh) {
    guarded_void("dfm_mesh_destroy", [&] { host_delete<MeshObject>(mesh); });
}

extern "C" DFM_API dfm_result dfm_mesh_get_info(const dfm_mesh* mesh, dfm_mesh_info* out) {
    constexpr const char* fn = "dfm_mesh_get_info";
    return guarded(fn, [&] {
        if (out == nullptr) return report(fn, DFM_ERROR_INVALID_ARGUMENT, "out is NULL");
        *out = dfm_mesh_info{};
        MeshObject* m = resolve_mesh(mesh);
        if (m == nullptr) return bad_handle(fn, "mesh", mesh);
        const MeshState& state = *m->state;
        const std::shared_ptr<const deform::MeshModel> model = state.current();
        out->bake_count = state.poses.undo_count();
        out->redo_count = state.poses.redo_count();
        const mesh::MeshSummary summary = mesh::summarize(model->mesh);
        const HostNumbering numbering(state, summary.vertices);
        out->vertex_count = numbering.host_count();
        out->surface_vertex_count = summary.vertices;
        out->triangle_count =
            numbering.identity() ? summary.faces : numbering.weld()->host_triangles.size();
        for (int c = 0; c < 3; ++c) {
            out->bounds_min[c] = summary.bounds.min[c];
            out->bounds_max[c] = summary.bounds.max[c];
        }
        out->diagonal = model->diagonal;
        out->components = summary.components;
        out->boundary_edges = summary.boundary_edges;
        return DFM_OK;
    });
}

extern "C" DFM_API dfm_result dfm_mesh_read_positions(const dfm_mesh* mesh,
                                                      const dfm_vec3_output* out) {
    constexpr const char* fn = "dfm_mesh_read_positions";
    return guarded(fn, [&] {
        MeshObject* m = resolve_mesh(mesh);
        if (m == nullptr) return bad_handle(fn, "mesh", mesh);
        dfm_result r = DFM_OK;
        m->state->poses.read_shown([&](const deform::MeshModel& bind,
                                       std::span<const glm::dvec3> shown) {
            const HostNumbering numbering(*m->state, bind.mesh.vertex_count());
            if (std::string e = check_vec3_output(out, numbering.host_count(), "out"); !e.empty()) {
                r = report(fn, DFM_ERROR_INVALID_ARGUMENT, e);
                return;
            }
            numbering.write_all(*out, shown);
        });
        return r;
    });
}

namespace {

// dfm_mesh_read_indices and _indices16: the calls' one opening (the mesh,
// the array, the host's vertex count within `max_vertices`, the room), then
// `write` with the host's triangles.
template <class Index, class Write>
dfm_result read_host_triangles(const char* fn, const dfm_mesh* mesh, Index* indices,
                               std::size_t capacity, std::size_t max_vertices, Write&& write) {
    return guarded(fn, [&] {
        MeshObject* m = resolve_mesh(mesh);
        if (m == nullptr) return bad_handle(fn, "mesh", mesh);
        if (indices == nullptr) return report(fn, DFM_ERROR_INVALID_ARGUMENT, "indices is NULL");
        const auto model = m->state->current();
        const HostNumbering numbering(*m->state, model->mesh.vertex_count());
        if (numbering.host_count() > max_vertices) {
            return report(fn, DFM_ERROR_OUT_OF_RANGE,
                          "the mesh has " + std::to_string(numbering.host_count()) +
                              " vertices, more than 16-bit indices reach (65,536)");
        }
        const auto& triangles =
            numbering.identity() ? model->mesh.triangles : numbering.weld()->host_triangles;
        if (capacity < 3 * triangles.size()) {
            return report(fn, DFM_ERROR_INVALID_ARGUMENT,
                          "room for " + std::to_string(capacity) + " indices, " +
                              std::to_string(3 * triangles.size()) + " needed");
        }
        write(triangles);
        return DFM_OK;
    });
}

}  // namespace

extern "C" DFM_API dfm_result dfm_mesh_read_indices(const dfm_mesh* mesh, uint32_t* indices,
                                                    size_t capacity) {
    return read_host_triangles(
        "dfm_mesh_read_indices", mesh, indices, capacity, SIZE_MAX, [&](const auto& triangles) {
            std::memcpy(indices, triangles.data(), triangles.size() * sizeof(mesh::Triangle));
        });
}

extern "C" DFM_API dfm_result dfm_mesh_read_normals(const dfm_mesh* mesh,
                                                    const dfm_vec3_output* out) {
    constexpr const char* fn = "dfm_mesh_read_normals";
    return guarded(fn, [&] {
        MeshObject* m = resolve_mesh(mesh);
        if (m == nullptr) return bad_handle(fn, "mesh", mesh);
        dfm_result r = DFM_OK;
        m->state->poses.read_shown([&](const deform::MeshModel& bind,
                                       std::span<const glm::dvec3> shown) {
            const HostNumbering numbering(*m->state, bind.mesh.vertex_count());
            if (std::string e = check_vec3_output(out, numbering.host_count(), "out"); !e.empty()) {
                r = report(fn, DFM_ERROR_INVALID_ARGUMENT, e);
                return;
            }
            std::vector<glm::dvec3> normals;
            mesh::compute_vertex_normals(bind.mesh, shown, normals);
            numbering.write_all(*out, normals);
        });
        return r;
    });
}

extern "C" DFM_API dfm_result dfm_mesh_read_surface_map(const dfm_mesh* mesh, uint32_t* lowest_copy,
                                                        size_t capacity) {
    constexpr const char* fn = "dfm_mesh_read_surface_map";
    return guarded(fn, [&] {
        MeshObject* m = resolve_mesh(mesh);
        if (m == nullptr) return bad_handle(fn, "mesh", mesh);
        if (lowest_copy == nullptr) {
            return report(fn, DFM_ERROR_INVALID_ARGUMENT, "lowest_copy is NULL");
        }
        const auto model = m->state->current();
        const HostNumbering numbering(*m->state, model->mesh.vertex_count());
        const std::size_t n = numbering.host_count();
        if (capacity < n) {
            return report(fn, DFM_ERROR_INVALID_ARGUMENT,
                          "room for " + std::to_string(capacity) + " entries, " +
                              std::to_string(n) + " needed");
        }
        for (std::size_t h = 0; h < n; ++h) {
            lowest_copy[h] = numbering.identity()
                                 ? static_cast<std::uint32_t>(h)
                                 : numbering.to_host(numbering.weld()->surface_of[h]);
        }
        return DFM_OK;
    });
}

extern "C" DFM_API dfm_result dfm_mesh_read_indices16(const dfm_mesh* mesh, uint16_t* indices,
                                                      size_t capacity) {
    return read_host_triangles(
        "dfm_mesh_read_indices16", mesh, indices, capacity, 65536, [&](const auto& triangles) {
            for (std::size_t t = 0; t < triangles.size(); ++t) {
                for (int c = 0; c < 3; ++c) {
                    indices[3 * t + c] = static_cast<std::uint16_t>(triangles[t][c]);
                }
            }
        });
}

extern "C" DFM_API dfm_result dfm_mesh_set_positions(dfm_mesh* mesh,
                                                     const dfm_vec3_input* positions) {
    constexpr const char* fn = "dfm_mesh_set_positions";
    return guarded(fn, [&] {
        MeshObject* m = resolve_mesh(mesh);
        if (m == nullptr) return bad_handle(fn, "mesh", mesh);
        if (std::string e = check_vec3_input(positions, "positions"); !e.empty()) {
            return report(fn, DFM_ERROR_INVALID_ARGUMENT, e);
        }
        const auto model = m->state->current();
        const HostNumbering numbering(*m->state, model->mesh.vertex_count());
        if (positions->count != numbering.host_count()) {
            return report(fn, DFM_ERROR_INVALID_ARGUMENT,
                          "positions->count is " + std::to_string(positions->count) +
                              ", the mesh has " + std::to_string(numbering.host_count()) +
                              " vertices");
        }
        std::vector<glm::dvec3> xyz(positions->count);
        for (std::size_t v = 0; v < xyz.size(); ++v) {
            xyz[v] = read_vec3(*positions, v);
            if (!std::isfinite(xyz[v].x) || !std::isfinite(xyz[v].y) || !std::isfinite(xyz[v].z)) {
                return report(fn, DFM_ERROR_NUMERICAL,
                              "vertex " + std::to_string(v) + " is not finite; nothing changed");
            }
        }
        xyz = numbering.surface_positions(xyz);
        auto posed = std::allocate_shared<deform::MeshModel>(
            HostAllocator<deform::MeshModel>(m->state->context->allocator));
        if (Status s = deform::bake_positions(*model, xyz, *posed); !s) return report(fn, s);
        if (Status s = m->state->poses.add_step(model, std::move(posed), nullptr); !s) {
            return report(fn, s);
        }
        log_damped_corrective(*m->state, fn);
        return DFM_OK;
    });
}

namespace {

// Undo and redo: a step of the mesh's rest poses back or forth.
dfm_result step_history(const char* fn, dfm_mesh* mesh, bool undo) {
    MeshObject* m = resolve_mesh(mesh);
    if (m == nullptr) return bad_handle(fn, "mesh", mesh);
    return guarded(fn, [&] {
        deform::RestPoses& poses = m->state->poses;
        if (!(undo ? poses.undo() : poses.redo())) {
            return report(fn, DFM_ERROR_NOT_FOUND,
                          undo ? "no bake to undo" : "no undone bake to redo");
        }
        return DFM_OK;
    });
}

}  // namespace

extern "C" DFM_API dfm_result dfm_mesh_undo_bake(dfm_mesh* mesh) {
    return step_history("dfm_mesh_undo_bake", mesh, true);
}

extern "C" DFM_API dfm_result dfm_mesh_redo_bake(dfm_mesh* mesh) {
    return step_history("dfm_mesh_redo_bake", mesh, false);
}
