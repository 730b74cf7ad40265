#include "dualform/api_edit.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/mat4x4.hpp>

#include "json/json_writer.hpp"

namespace dfm::cli {

namespace {

ToolStatus check_vertex(std::uint32_t v, const ScenarioMesh& mesh, const std::string& what) {
    if (v < mesh.info.vertex_count) return ToolStatus::ok();
    return ToolStatus(DFM_ERROR_OUT_OF_RANGE,
                      what + ": vertex " + std::to_string(v) + " is out of range (the mesh has " +
                          std::to_string(mesh.info.vertex_count) + " vertices)");
}

ToolStatus read_roi(RoiPtr roi, ScenarioRoi& out) {
    std::size_t count = 0;
    if (ToolStatus s = api_status(dfm_roi_count(roi.get(), &count)); !s) return s;
    out.vertices.resize(count);
    if (ToolStatus s = api_status(dfm_roi_read(roi.get(), out.vertices.data(), count)); !s)
        return s;
    out.roi = std::move(roi);
    return ToolStatus::ok();
}

ToolStatus ball(const BallSelection& spec, const ScenarioMesh& mesh, const std::string& what,
                ScenarioRoi& out) {
    if (ToolStatus s = check_vertex(spec.center, mesh, what + ".ball.center"); !s) return s;
    dfm_roi* roi = nullptr;
    if (ToolStatus s =
            api_status(dfm_roi_ball(mesh.mesh.get(), spec.center, spec.radius, &roi), what);
        !s) {
        return s;
    }
    return read_roi(RoiPtr(roi), out);
}

// The vertex a click picks: the nearest corner of the face it hits.
ToolStatus click_vertex(const ScenarioMesh& mesh, const dfm_camera& camera, glm::dvec2 pixel,
                        const std::string& what, std::uint32_t& out) {
    dfm_hit hit = {};
    if (ToolStatus s =
            api_status(dfm_mesh_pick(mesh.mesh.get(), &camera, pixel.x, pixel.y, &hit), what);
        !s) {
        return s;
    }
    if (!hit.hit) {
        std::string message = what + ": the click at [";
        json::append_number(message, pixel.x);
        message += ", ";
        json::append_number(message, pixel.y);
        message += "] hits nothing";
        return ToolStatus(DFM_ERROR_INVALID_ARGUMENT, std::move(message));
    }
    out = hit.vertex;
    return ToolStatus::ok();
}

// Rotation about the pivot first, then translation: the order a user
// dragging a rotated handle expects.
void group_targets(const HandleSpec& spec, const std::vector<std::uint32_t>& group,
                   const ScenarioMesh& mesh, std::vector<glm::dvec3>& targets) {
    if (!spec.targets.empty()) {
        targets.insert(targets.end(), spec.targets.begin(), spec.targets.end());
        return;
    }
    glm::dmat4 motion(1.0);
    if (spec.translate) motion = glm::translate(motion, *spec.translate * mesh.info.diagonal);
    if (spec.rotate) {
        glm::dvec3 pivot = spec.rotate->pivot;
        if (spec.rotate->pivot_is_centroid) {
            pivot = glm::dvec3(0.0);
            for (std::uint32_t v : group) pivot += mesh.rest[v];
            pivot /= static_cast<double>(group.size());
        }
        motion = glm::translate(motion, pivot);
        motion = glm::rotate(motion, spec.rotate->degrees * std::numbers::pi / 180.0,
                             glm::normalize(spec.rotate->axis));
        motion = glm::translate(motion, -pivot);
    }
    for (std::uint32_t v : group) {
        targets.push_back(glm::dvec3(motion * glm::dvec4(mesh.rest[v], 1.0)));
    }
}

}  // namespace

ToolStatus open_scenario_mesh(const Scenario& scenario, ScenarioMesh& out,
                              std::uint32_t worker_count) {
    if (ToolStatus s = create_context(out.context, worker_count); !s) return s;
    const std::filesystem::path written(scenario.mesh);
    const std::string path = scenario.mesh.starts_with("model:") || written.is_absolute()
                                 ? scenario.mesh
                                 : (scenario.base_dir / written).string();
    dfm_mesh* mesh = nullptr;
    if (ToolStatus s = api_status(dfm_mesh_load(out.context.get(), path.c_str(), &mesh), "mesh");
        !s) {
        return s;
    }
    out.mesh.reset(mesh);
    if (scenario.subdivide > 0) {
        dfm_mesh* fine = nullptr;
        if (ToolStatus s = api_status(
                dfm_mesh_subdivide(out.mesh.get(), static_cast<std::uint32_t>(scenario.subdivide),
                                   &fine),
                "subdivide");
            !s) {
            return s;
        }
        out.mesh.reset(fine);
    }
    if (scenario.pose) {
        std::uint32_t animation = scenario.pose->animation_index;
        if (scenario.pose->animation_name) {
            if (ToolStatus s = api_status(
                    dfm_mesh_find_animation(out.mesh.get(), scenario.pose->animation_name->c_str(),
                                            &animation),
                    "pose.animation");
                !s) {
                return s;
            }
        }
        if (ToolStatus s = api_status(
                dfm_mesh_set_pose_animation(out.mesh.get(), animation, scenario.pose->time),
                "pose");
            !s) {
            return s;
        }
    }
    return refresh_scenario_mesh(out);
}

ToolStatus refresh_scenario_mesh(ScenarioMesh& mesh) {
    if (ToolStatus s = api_status(dfm_mesh_get_info(mesh.mesh.get(), &mesh.info)); !s) return s;
    mesh.rest.resize(mesh.info.vertex_count);
    dfm_vec3_output positions = {};
    positions.data = mesh.rest.data();
    positions.count = mesh.rest.size();
    positions.type = DFM_SCALAR_FLOAT64;
    if (ToolStatus s = api_status(dfm_mesh_read_positions(mesh.mesh.get(), &positions)); !s)
        return s;
    mesh.lowest_copy.resize(mesh.info.vertex_count);
    return api_status(dfm_mesh_read_surface_map(mesh.mesh.get(), mesh.lowest_copy.data(),
                                                mesh.lowest_copy.size()));
}

ToolStatus read_mesh_indices(const ScenarioMesh& mesh, std::vector<std::uint32_t>& out) {
    out.resize(3 * mesh.info.triangle_count);
    return api_status(dfm_mesh_read_indices(mesh.mesh.get(), out.data(), out.size()));
}

ToolStatus select_roi(const RoiSpec& spec, const ScenarioMesh& mesh, ScenarioRoi& out) {
    out = ScenarioRoi{};
    dfm_mesh* m = mesh.mesh.get();
    dfm_roi* roi = nullptr;
    switch (spec.kind) {
        case RoiSpec::Kind::water_fill: {
            dfm_water_fill_diagnosis diagnosis = {};
            if (ToolStatus s = api_status(
                    dfm_roi_water_fill(m, spec.first, spec.last, &roi, &diagnosis), "roi");
                !s) {
                return s;
            }
            out.diagnosis = diagnosis;
            break;
        }
        case RoiSpec::Kind::water_fill_clicks: {
            // Each click is picked here, as dfm_roi_water_fill_clicks would,
            // so that a miss names the scenario's field.
            const std::string what = "roi.water_fill_clicks";
            std::uint32_t first = 0;
            std::uint32_t last = 0;
            if (ToolStatus s =
                    click_vertex(mesh, spec.camera, spec.first_pixel, what + ".first", first);
                !s) {
                return s;
            }
            if (ToolStatus s =
                    click_vertex(mesh, spec.camera, spec.last_pixel, what + ".last", last);
                !s) {
                return s;
            }
            dfm_water_fill_diagnosis diagnosis = {};
            if (ToolStatus s =
                    api_status(dfm_roi_water_fill(m, first, last, &roi, &diagnosis), what);
                !s) {
                return s;
            }
            out.diagnosis = diagnosis;
            break;
        }
        case RoiSpec::Kind::ball: return ball(spec.ball, mesh, "roi", out);
        case RoiSpec::Kind::vertices:
            for (std::uint32_t v : spec.vertices) {
                if (ToolStatus s = check_vertex(v, mesh, "roi.vertices"); !s) return s;
            }
            if (ToolStatus s = api_status(
                    dfm_roi_from_vertices(m, spec.vertices.data(), spec.vertices.size(), &roi),
                    "roi.vertices");
                !s) {
                return s;
            }
            break;
        case RoiSpec::Kind::all:
            if (ToolStatus s = api_status(dfm_roi_all(m, &roi), "roi"); !s) return s;
            break;
    }
    std::optional<dfm_water_fill_diagnosis> diagnosis = out.diagnosis;
    if (ToolStatus s = read_roi(RoiPtr(roi), out); !s) return s;
    out.diagnosis = diagnosis;
    return ToolStatus::ok();
}

ToolStatus resolve_scenario_edit(const Scenario& scenario, const ScenarioMesh& mesh,
                                 ScenarioEdit& out) {
    out = ScenarioEdit{};
    if (ToolStatus s = select_roi(scenario.roi, mesh, out.roi); !s) return s;
    const std::vector<std::uint32_t>& roi = out.roi.vertices;
    for (std::size_t g = 0; g < scenario.handles.size(); ++g) {
        const HandleSpec& spec = scenario.handles[g];
        const std::string what = "handles[" + std::to_string(g) + "]";
        std::vector<std::uint32_t> group;
        if (spec.ball) {
            ScenarioRoi selected;
            if (ToolStatus s = ball(*spec.ball, mesh, what, selected); !s) return s;
            group = std::move(selected.vertices);
        } else {
            for (std::uint32_t v : spec.vertices) {
                if (ToolStatus s = check_vertex(v, mesh, what + ".vertices"); !s) return s;
            }
            group = spec.vertices;
        }
        for (std::uint32_t v : group) {
            if (!std::binary_search(roi.begin(), roi.end(), mesh.lowest_copy[v])) {
                return ToolStatus(DFM_ERROR_INVALID_ARGUMENT,
                                  what + ": vertex " + std::to_string(v) + " is outside the ROI");
            }
        }
        group_targets(spec, group, mesh, out.targets);
        out.groups.push_back(std::move(group));
    }
    const SolverSpec& solver = scenario.solver;
    if (solver.tolerance) out.solver.tolerance = *solver.tolerance;
    if (solver.max_iterations) {
        out.solver.max_iterations = static_cast<std::uint32_t>(*solver.max_iterations);
    }
    if (solver.handle_weight) out.solver.handle_weight = *solver.handle_weight;
    if (solver.method) {
        out.solver.method =
            *solver.method == "paper" ? DFM_METHOD_PAPER : DFM_METHOD_FITTED_ROTATIONS;
    }
    return ToolStatus::ok();
}

ToolStatus start_session(const ScenarioMesh& mesh, const ScenarioEdit& edit, SessionPtr& out) {
    std::vector<dfm_handle_group> groups(edit.groups.size());
    for (std::size_t g = 0; g < groups.size(); ++g) {
        groups[g].vertices = edit.groups[g].data();
        groups[g].count = edit.groups[g].size();
    }
    dfm_session_desc desc = {};
    desc.roi = edit.roi.roi.get();
    desc.groups = groups.data();
    desc.group_count = groups.size();
    desc.solver = edit.solver;
    dfm_session* session = nullptr;
    if (ToolStatus s = api_status(dfm_session_create(mesh.mesh.get(), &desc, &session)); !s)
        return s;
    out.reset(session);
    dfm_vec3_input targets = {};
    targets.data = edit.targets.data();
    targets.count = edit.targets.size();
    targets.type = DFM_SCALAR_FLOAT64;
    return api_status(dfm_session_set_targets(out.get(), &targets));
}

}  // namespace dfm::cli
