#include "dualform/edit_setup.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "core/number_text.hpp"
#include "dualform/pick_camera.hpp"
#include "environment/host_environment.hpp"
#include "mesh/load.hpp"
#include "mesh/model_cache.hpp"
#include "mesh/subdivide.hpp"
#include "pick/pick.hpp"
#include "roi/ball_selection.hpp"

namespace dfm::cli {

bool parse_preconditioner(std::string_view name, deform::Preconditioner& out) {
    for (auto p : {deform::Preconditioner::cholesky, deform::Preconditioner::incomplete_cholesky,
                   deform::Preconditioner::jacobi}) {
        if (name == deform::preconditioner_name(p)) {
            out = p;
            return true;
        }
    }
    return false;
}

namespace {

Status check_vertex(std::uint32_t v, const deform::MeshModel& model, const std::string& what) {
    if (v < model.mesh.vertex_count()) return Status::ok();
    return Status(Errc::out_of_range, what + ": vertex " + std::to_string(v) +
                                          " is out of range (the mesh has " +
                                          std::to_string(model.mesh.vertex_count()) + " vertices)");
}

Status select(const BallSelection& ball, const deform::MeshModel& model, const std::string& what,
              std::vector<std::uint32_t>& out) {
    if (Status s = check_vertex(ball.center, model, what + ".ball.center"); !s) return s;
    return roi::select_ball(model.mesh.positions, model.vertex_neighbors, ball.center,
                            ball.radius * model.diagonal, out);
}

Status water_fill(std::uint32_t first, std::uint32_t last, const deform::MeshModel& model,
                  const std::string& what, std::vector<std::uint32_t>& roi,
                  std::optional<roi::WaterFillDiagnosis>& diagnosis) {
    const roi::SurfaceView surface{model.mesh.positions, model.mesh.triangles,
                                   &model.vertex_neighbors, model.vertex_face_offsets,
                                   model.vertex_faces};
    roi::WaterFill fill;
    if (Status s = roi::water_fill(surface, first, last, fill); !s) {
        return Status(s.code(), what + ": " + s.message());
    }
    roi = std::move(fill.vertices);
    diagnosis = fill.diagnosis;
    return Status::ok();
}

// The vertex a click picks: the nearest vertex of the face it hits.
Status click_vertex(const pick::EmbreeScene& scene, const dfm_camera& camera, glm::dvec2 pixel,
                    const std::string& what, std::uint32_t& out) {
    std::optional<pick::Hit> hit;
    if (Status s = pick::pick_pixel(scene, to_pick_camera(camera), pixel, hit); !s) {
        return Status(s.code(), what + ": " + s.message());
    }
    if (!hit) {
        std::string message = what;
        message += ": the click at [";
        append_number(message, pixel.x);
        message += ", ";
        append_number(message, pixel.y);
        message += "] hits nothing";
        return Status(Errc::invalid_argument, std::move(message));
    }
    out = hit->vertex;
    return Status::ok();
}

Status water_fill_clicks(const RoiSpec& spec, const deform::MeshModel& model,
                         std::vector<std::uint32_t>& roi,
                         std::optional<roi::WaterFillDiagnosis>& diagnosis) {
    const std::string what = "roi.water_fill_clicks";
    pick::EmbreeScene scene;
    if (Status s = pick::EmbreeScene::create(model.mesh.positions, model.mesh.triangles, scene);
        !s) {
        return Status(s.code(), what + ": " + s.message());
    }
    std::uint32_t first = 0;
    std::uint32_t last = 0;
    if (Status s = click_vertex(scene, spec.camera, spec.first_pixel, what + ".first", first); !s) {
        return s;
    }
    if (Status s = click_vertex(scene, spec.camera, spec.last_pixel, what + ".last", last); !s) {
        return s;
    }
    return water_fill(first, last, model, what, roi, diagnosis);
}

}  // namespace

Status resolve_roi(const RoiSpec& spec, const deform::MeshModel& model,
                   std::vector<std::uint32_t>& roi,
                   std::optional<roi::WaterFillDiagnosis>& diagnosis) {
    diagnosis.reset();
    switch (spec.kind) {
        case RoiSpec::Kind::water_fill:
            return water_fill(spec.first, spec.last, model, "roi", roi, diagnosis);
        case RoiSpec::Kind::water_fill_clicks:
            return water_fill_clicks(spec, model, roi, diagnosis);
        case RoiSpec::Kind::ball: return select(spec.ball, model, "roi", roi);
        case RoiSpec::Kind::vertices:
            for (std::uint32_t v : spec.vertices) {
                if (Status s = check_vertex(v, model, "roi.vertices"); !s) return s;
            }
            roi = spec.vertices;
            std::sort(roi.begin(), roi.end());
            roi.erase(std::unique(roi.begin(), roi.end()), roi.end());
            return Status::ok();
        case RoiSpec::Kind::all:
            roi.resize(model.mesh.vertex_count());
            for (std::uint32_t v = 0; v < roi.size(); ++v) roi[v] = v;
            return Status::ok();
    }
    return Status(Errc::invalid_argument, "roi: unknown kind");
}

namespace {

// Rotation about the pivot first, then translation: the order a user
// dragging a rotated handle expects.
Status group_targets(const HandleSpec& spec, const std::vector<std::uint32_t>& group,
                     const deform::MeshModel& model, const std::string& what,
                     std::vector<glm::dvec3>& targets) {
    const auto& rest = model.mesh.positions;
    if (!spec.targets.empty()) {
        targets.insert(targets.end(), spec.targets.begin(), spec.targets.end());
        return Status::ok();
    }
    glm::dmat4 motion(1.0);
    if (spec.translate) motion = glm::translate(motion, *spec.translate * model.diagonal);
    if (spec.rotate) {
        glm::dvec3 pivot = spec.rotate->pivot;
        if (spec.rotate->pivot_is_centroid) {
            pivot = glm::dvec3(0.0);
            for (std::uint32_t v : group) pivot += rest[v];
            pivot /= static_cast<double>(group.size());
        }
        const double length = glm::length(spec.rotate->axis);
        if (!(length > 0.0)) return Status(Errc::invalid_argument, what + ".rotate.axis: is zero");
        motion = glm::translate(motion, pivot);
        motion = glm::rotate(motion, spec.rotate->degrees * std::numbers::pi / 180.0,
                             spec.rotate->axis / length);
        motion = glm::translate(motion, -pivot);
    }
    for (std::uint32_t v : group) targets.push_back(glm::dvec3(motion * glm::dvec4(rest[v], 1.0)));
    return Status::ok();
}

}  // namespace

Status resolve_edit(const Scenario& scenario, const deform::MeshModel& model, EditSetup& out) {
    out = EditSetup{};
    std::optional<roi::WaterFillDiagnosis> diagnosis;
    if (Status s = resolve_roi(scenario.roi, model, out.roi, diagnosis); !s) return s;
    out.in_roi.assign(model.mesh.vertex_count(), 0);
    for (std::uint32_t v : out.roi) out.in_roi[v] = 1;
    for (std::size_t g = 0; g < scenario.handles.size(); ++g) {
        const HandleSpec& spec = scenario.handles[g];
        const std::string what = "handles[" + std::to_string(g) + "]";
        std::vector<std::uint32_t> group;
        if (spec.ball) {
            if (Status s = select(*spec.ball, model, what, group); !s) return s;
        } else {
            for (std::uint32_t v : spec.vertices) {
                if (Status s = check_vertex(v, model, what + ".vertices"); !s) return s;
            }
            group = spec.vertices;
        }
        for (std::uint32_t v : group) {
            if (!out.in_roi[v]) {
                return Status(Errc::invalid_argument,
                              what + ": vertex " + std::to_string(v) + " is outside the ROI");
            }
        }
        if (Status s = group_targets(spec, group, model, what, out.targets); !s) return s;
        out.handle_groups.push_back(std::move(group));
    }
    const SolverSpec& solver = scenario.solver;
    if (solver.tolerance) out.settings.tolerance = *solver.tolerance;
    if (solver.max_iterations) out.settings.max_iterations = *solver.max_iterations;
    if (solver.handle_weight) out.settings.handle_weight = *solver.handle_weight;
    if (solver.method) {
        out.settings.method = *solver.method == "paper" ? deform::DeformMethod::paper
                                                        : deform::DeformMethod::fitted_rotations;
    }
    return Status::ok();
}

Status load_scenario_model(const Scenario& scenario, deform::MeshModel& model) {
    std::filesystem::path path;
    if (Status s = mesh::resolve_mesh_spec(scenario.mesh, scenario.base_dir,
                                           tools::models_folder_from_environment(), path);
        !s) {
        return Status(s.code(), "mesh: " + s.message());
    }
    mesh::Mesh m;
    if (Status s = mesh::load_mesh(path, m); !s) return s;
    for (int k = 0; k < scenario.subdivide; ++k) m = mesh::subdivide_loop(m);
    model = deform::build_mesh_model(std::move(m));
    return Status::ok();
}

}  // namespace dfm::cli
