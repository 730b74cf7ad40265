#include <cmath>
#include <optional>

#include "c_boundary.hpp"
#include "host_numbering.hpp"
#include "objects.hpp"
#include "pick/pick.hpp"
#include "pick_camera.hpp"
#include "roi/ball_selection.hpp"
#include "roi/boundary.hpp"
#include "roi/rings.hpp"
#include "roi/set_ops.hpp"
#include "roi/vertex_list.hpp"
#include "roi/water_fill.hpp"

using namespace dfm;
using namespace dfm::sdk;

namespace {

dfm_result make_roi(const std::shared_ptr<MeshState>& mesh, std::vector<std::uint32_t> vertices,
                    dfm_roi** out) {
    *out = host_new<RoiObject>(*mesh->context, mesh, std::move(vertices));
    return DFM_OK;
}

roi::SurfaceView surface_of(const deform::MeshModel& model) {
    return {model.mesh.positions, model.mesh.triangles, &model.vertex_neighbors,
            model.vertex_face_offsets, model.vertex_faces};
}

// `first` and `last` are surface vertices.
dfm_result fill(const char* fn, MeshObject* mesh, std::uint32_t first, std::uint32_t last,
                dfm_roi** out, dfm_water_fill_diagnosis* diagnosis) {
    const auto model = mesh->state->current();
    const HostNumbering numbering(*mesh->state, model->mesh.vertex_count());
    roi::WaterFill result;
    if (Status s = roi::water_fill(surface_of(*model), first, last, result); !s) {
        return report(fn, s);
    }
    if (diagnosis != nullptr) {
        diagnosis->loops = result.diagnosis.loops;
        diagnosis->bounded_by_last_loop = result.diagnosis.bounded_by_last_loop;
        diagnosis->suspect = result.diagnosis.suspect;
    }
    if (result.diagnosis.suspect) {
        mesh->state->context->emit(
            DFM_LOG_WARNING, DFM_LOG_ID_WATER_FILL_SUSPECT,
            "Water-Filling from vertex " + std::to_string(numbering.to_host(first)) + " to " +
                std::to_string(numbering.to_host(last)) + " gave " +
                std::to_string(result.vertices.size()) + " vertices bounded by " +
                std::to_string(result.diagnosis.loops) +
                " cut loops: it most likely leaked past the intended part");
    }
    return make_roi(mesh->state, std::move(result.vertices), out);
}

// The common prologue of calls that make a ROI from another one.
bool begin(const char* fn, dfm_roi** out, dfm_result& result) {
    if (out == nullptr) {
        result = report(fn, DFM_ERROR_INVALID_ARGUMENT, "out is NULL");
        return false;
    }
    *out = nullptr;
    return true;
}

}  // namespace

extern "C" DFM_API dfm_result dfm_roi_water_fill(dfm_mesh* mesh, uint32_t first, uint32_t last,
                                                 dfm_roi** out,
                                                 dfm_water_fill_diagnosis* diagnosis) {
    constexpr const char* fn = "dfm_roi_water_fill";
    return guarded(fn, [&] {
        dfm_result r = DFM_OK;
        if (!begin(fn, out, r)) return r;
        if (diagnosis != nullptr) *diagnosis = dfm_water_fill_diagnosis{};
        MeshObject* m = resolve_mesh(mesh);
        if (m == nullptr) return bad_handle(fn, "mesh", mesh);
        const HostNumbering numbering(*m->state, m->state->current()->mesh.vertex_count());
        std::uint32_t a = 0, b = 0;
        if (Status s = numbering.to_surface(first, "first", a); !s) return report(fn, s);
        if (Status s = numbering.to_surface(last, "last", b); !s) return report(fn, s);
        return guarded(fn, [&] { return fill(fn, m, a, b, out, diagnosis); });
    });
}

extern "C" DFM_API dfm_result dfm_roi_water_fill_clicks(dfm_mesh* mesh, const dfm_camera* camera,
                                                        const double first_pixel[2],
                                                        const double last_pixel[2], dfm_roi** out,
                                                        dfm_water_fill_diagnosis* diagnosis) {
    constexpr const char* fn = "dfm_roi_water_fill_clicks";
    return guarded(fn, [&] {
        dfm_result r = DFM_OK;
        if (!begin(fn, out, r)) return r;
        if (diagnosis != nullptr) *diagnosis = dfm_water_fill_diagnosis{};
        MeshObject* m = resolve_mesh(mesh);
        if (m == nullptr) return bad_handle(fn, "mesh", mesh);
        if (camera == nullptr || first_pixel == nullptr || last_pixel == nullptr) {
            return report(fn, DFM_ERROR_INVALID_ARGUMENT, "camera or a pixel is NULL");
        }
        const pick::Camera c = to_camera(*camera);
        if (Status s = pick::check_camera(c); !s) return report(fn, s);
        std::optional<pick::Hit> hits[2];
        const double* pixels[2] = {first_pixel, last_pixel};
        for (int k = 0; k < 2; ++k) {
            if (!std::isfinite(pixels[k][0]) || !std::isfinite(pixels[k][1])) {
                return report(
                    fn, DFM_ERROR_INVALID_ARGUMENT,
                    std::string(k == 0 ? "the first" : "the last") + " pixel is not finite");
            }
            const Status s = with_scene(*m->state, [&](const pick::EmbreeScene& scene) {
                return pick::pick_pixel(scene, c, {pixels[k][0], pixels[k][1]}, hits[k]);
            });
            if (!s) return report(fn, s);
            if (!hits[k]) {
                return report(fn, DFM_ERROR_NOT_FOUND,
                              std::string(k == 0 ? "the first" : "the last") + " click (" +
                                  std::to_string(pixels[k][0]) + ", " +
                                  std::to_string(pixels[k][1]) + ") misses the mesh");
            }
        }
        return fill(fn, m, hits[0]->vertex, hits[1]->vertex, out, diagnosis);
    });
}

extern "C" DFM_API dfm_result dfm_roi_from_vertices(dfm_mesh* mesh, const uint32_t* vertices,
                                                    size_t count, dfm_roi** out) {
    constexpr const char* fn = "dfm_roi_from_vertices";
    return guarded(fn, [&] {
        dfm_result r = DFM_OK;
        if (!begin(fn, out, r)) return r;
        MeshObject* m = resolve_mesh(mesh);
        if (m == nullptr) return bad_handle(fn, "mesh", mesh);
        if (vertices == nullptr && count > 0) {
            return report(fn, DFM_ERROR_INVALID_ARGUMENT, "vertices is NULL");
        }
        if (count == 0) return report(fn, DFM_ERROR_INVALID_ARGUMENT, "the list is empty");
        const auto model = m->state->current();
        const HostNumbering numbering(*m->state, model->mesh.vertex_count());
        std::vector<std::uint32_t> surface;
        if (Status s = numbering.to_surface({vertices, count}, "vertices", surface); !s) {
            return report(fn, s);
        }
        std::vector<std::uint32_t> list;
        if (Status s = roi::select_vertices(surface, model->mesh.vertex_count(), list); !s) {
            return report(fn, s);
        }
        return make_roi(m->state, std::move(list), out);
    });
}

extern "C" DFM_API dfm_result dfm_roi_ball(dfm_mesh* mesh, uint32_t center, double radius,
                                           dfm_roi** out) {
    constexpr const char* fn = "dfm_roi_ball";
    return guarded(fn, [&] {
        dfm_result r = DFM_OK;
        if (!begin(fn, out, r)) return r;
        MeshObject* m = resolve_mesh(mesh);
        if (m == nullptr) return bad_handle(fn, "mesh", mesh);
        if (!(radius >= 0.0) || !std::isfinite(radius)) {
            return report(fn, DFM_ERROR_INVALID_ARGUMENT, "radius must be finite and not negative");
        }
        const auto model = m->state->current();
        std::uint32_t surface_center = 0;
        if (Status s = HostNumbering(*m->state, model->mesh.vertex_count())
                           .to_surface(center, "center", surface_center);
            !s) {
            return report(fn, s);
        }
        std::vector<std::uint32_t> list;
        if (Status s = roi::select_ball(model->mesh.positions, model->vertex_neighbors,
                                        surface_center, radius * model->diagonal, list);
            !s) {
            return report(fn, s);
        }
        return make_roi(m->state, std::move(list), out);
    });
}

extern "C" DFM_API dfm_result dfm_roi_all(dfm_mesh* mesh, dfm_roi** out) {
    constexpr const char* fn = "dfm_roi_all";
    return guarded(fn, [&] {
        dfm_result r = DFM_OK;
        if (!begin(fn, out, r)) return r;
        MeshObject* m = resolve_mesh(mesh);
        if (m == nullptr) return bad_handle(fn, "mesh", mesh);
        std::vector<std::uint32_t> list(m->state->current()->mesh.vertex_count());
        for (std::size_t i = 0; i < list.size(); ++i) list[i] = static_cast<std::uint32_t>(i);
        return make_roi(m->state, std::move(list), out);
    });
}

extern "C" DFM_API dfm_result dfm_roi_grow(const dfm_roi* roi, int rings, dfm_roi** out) {
    constexpr const char* fn = "dfm_roi_grow";
    return guarded(fn, [&] {
        dfm_result r = DFM_OK;
        if (!begin(fn, out, r)) return r;
        RoiObject* region = resolve_roi(roi);
        if (region == nullptr) return bad_handle(fn, "roi", roi);
        const auto model = region->mesh->current();
        std::vector<std::uint32_t> list;
        const Status s =
            rings >= 0 ? roi::grow_rings(model->vertex_neighbors, region->vertices,
                                         static_cast<std::uint32_t>(rings), list)
                       : roi::shrink_rings(model->vertex_neighbors, region->vertices,
                                           static_cast<std::uint32_t>(-(rings + 1)) + 1u, list);
        if (!s) return report(fn, s);
        if (list.empty()) {
            return report(fn, DFM_ERROR_INVALID_ARGUMENT,
                          "shrinking by " + std::to_string(-static_cast<long long>(rings)) +
                              " rings leaves nothing");
        }
        return make_roi(region->mesh, std::move(list), out);
    });
}

namespace {

dfm_result set_operation(const char* fn, const dfm_roi* a, const dfm_roi* b, dfm_roi** out,
                         bool is_union) {
    return guarded(fn, [&] {
        dfm_result r = DFM_OK;
        if (!begin(fn, out, r)) return r;
        const RoiObject* ra = resolve_roi(a);
        if (ra == nullptr) return bad_handle(fn, "a", a);
        const RoiObject* rb = resolve_roi(b);
        if (rb == nullptr) return bad_handle(fn, "b", b);
        if (ra->mesh != rb->mesh) {
            return report(fn, DFM_ERROR_INVALID_ARGUMENT, "a and b belong to different meshes");
        }
        std::vector<std::uint32_t> list;
        const std::size_t n = ra->mesh->current()->mesh.vertex_count();
        const Status s = is_union ? roi::roi_union(ra->vertices, rb->vertices, n, list)
                                  : roi::roi_difference(ra->vertices, rb->vertices, n, list);
        if (!s) return report(fn, s);
        if (list.empty()) return report(fn, DFM_ERROR_INVALID_ARGUMENT, "the result is empty");
        return make_roi(ra->mesh, std::move(list), out);
    });
}

}  // namespace

extern "C" DFM_API dfm_result dfm_roi_union(const dfm_roi* a, const dfm_roi* b, dfm_roi** out) {
    return set_operation("dfm_roi_union", a, b, out, true);
}

extern "C" DFM_API dfm_result dfm_roi_difference(const dfm_roi* a, const dfm_roi* b,
                                                 dfm_roi** out) {
    return set_operation("dfm_roi_difference", a, b, out, false);
}

extern "C" DFM_API dfm_result dfm_roi_boundary(const dfm_roi* roi, dfm_roi** out) {
    constexpr const char* fn = "dfm_roi_boundary";
    return guarded(fn, [&] {
        dfm_result r = DFM_OK;
        if (!begin(fn, out, r)) return r;
        RoiObject* region = resolve_roi(roi);
        if (region == nullptr) return bad_handle(fn, "roi", roi);
        std::vector<std::uint32_t> list;
        if (Status s = roi::boundary_vertices(region->mesh->current()->vertex_neighbors,
                                              region->vertices, list);
            !s) {
            return report(fn, s);
        }
        if (list.empty()) {
            return report(fn, DFM_ERROR_NOT_FOUND, "the region has no boundary (it is everything)");
        }
        return make_roi(region->mesh, std::move(list), out);
    });
}

extern "C" DFM_API dfm_result dfm_roi_count(const dfm_roi* roi, size_t* out) {
    constexpr const char* fn = "dfm_roi_count";
    return guarded(fn, [&] {
        if (out == nullptr) return report(fn, DFM_ERROR_INVALID_ARGUMENT, "out is NULL");
        *out = 0;
        RoiObject* region = resolve_roi(roi);
        if (region == nullptr) return bad_handle(fn, "roi", roi);
        *out = region->vertices.size();
        return DFM_OK;
    });
}

extern "C" DFM_API dfm_result dfm_roi_read(const dfm_roi* roi, uint32_t* vertices,
                                           size_t capacity) {
    constexpr const char* fn = "dfm_roi_read";
    return guarded(fn, [&] {
        RoiObject* region = resolve_roi(roi);
        if (region == nullptr) return bad_handle(fn, "roi", roi);
        if (vertices == nullptr) return report(fn, DFM_ERROR_INVALID_ARGUMENT, "vertices is NULL");
        if (capacity < region->vertices.size()) {
            return report(fn, DFM_ERROR_INVALID_ARGUMENT,
                          "room for " + std::to_string(capacity) + " vertices, " +
                              std::to_string(region->vertices.size()) + " needed");
        }
        std::copy(region->vertices.begin(), region->vertices.end(), vertices);
        HostNumbering(*region->mesh, 0).to_host({vertices, region->vertices.size()});
        return DFM_OK;
    });
}

extern "C" DFM_API void dfm_roi_destroy(dfm_roi* roi) {
    guarded_void("dfm_roi_destroy", [&] { host_delete<RoiObject>(roi); });
}
