#include "editor.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>

#include "json/json_writer.hpp"

namespace viewer {

namespace {

constexpr double pi = 3.14159265358979323846;

using Matrix = std::array<double, 16>;

Matrix identity() {
    Matrix m{};
    for (int i = 0; i < 4; ++i) m[5 * i] = 1.0;
    return m;
}

Matrix multiply(const Matrix& a, const Matrix& b) {
    Matrix r{};
    for (int col = 0; col < 4; ++col) {
        for (int row = 0; row < 4; ++row) {
            double sum = 0.0;
            for (int k = 0; k < 4; ++k) sum += a[4 * k + row] * b[4 * col + k];
            r[4 * col + row] = sum;
        }
    }
    return r;
}

Matrix translation(const Vec3& t) {
    Matrix m = identity();
    for (int c = 0; c < 3; ++c) m[12 + c] = t[c];
    return m;
}

// Rotation by `angle` radians about the unit `axis` (Rodrigues).
Matrix rotation(const Vec3& axis, double angle) {
    const double c = std::cos(angle), s = std::sin(angle), t = 1.0 - c;
    const double x = axis[0], y = axis[1], z = axis[2];
    Matrix m = identity();
    m[0] = t * x * x + c;
    m[1] = t * x * y + s * z;
    m[2] = t * x * z - s * y;
    m[4] = t * x * y - s * z;
    m[5] = t * y * y + c;
    m[6] = t * y * z + s * x;
    m[8] = t * x * z + s * y;
    m[9] = t * y * z - s * x;
    m[10] = t * z * z + c;
    return m;
}

Vec3 apply(const Matrix& m, const Vec3& p) {
    Vec3 r{};
    for (int c = 0; c < 3; ++c) r[c] = m[c] * p[0] + m[4 + c] * p[1] + m[8 + c] * p[2] + m[12 + c];
    return r;
}

}  // namespace

Editor::Editor(dfm_context* context, dfm_vk_renderer* renderer)
    : context_(context), renderer_(renderer) {
    solver_.tolerance = 1e-5;
    solver_.max_iterations = 100;
    solver_.handle_weight = 1.0;
    solver_.method = DFM_METHOD_FITTED_ROTATIONS;
}

Editor::~Editor() {
    dfm_session_destroy(session_);
    dfm_roi_destroy(roi_);
    dfm_mesh_destroy(mesh_);
}

bool Editor::report(dfm_result result, const char* call) const {
    if (result == DFM_OK) return true;
    last_error_ =
        std::string(call) + ": " + dfm_result_name(result) + ": " + dfm_last_error_message();
    std::fprintf(stderr, "viewer: %s\n", last_error_.c_str());
    return false;
}

bool Editor::open(const std::string& mesh_spec, int width, int height) {
    dfm_mesh* mesh = nullptr;
    if (!report(dfm_mesh_load(context_, mesh_spec.c_str(), &mesh), "dfm_mesh_load")) return false;
    return open_loaded(mesh, mesh_spec, width, height);
}

bool Editor::open_loaded(dfm_mesh* mesh, const std::string& mesh_spec, int width, int height) {
    mesh_ = mesh;
    mesh_spec_ = mesh_spec;
    if (!report(dfm_mesh_get_info(mesh_, &info_), "dfm_mesh_get_info")) return false;
    indices_.resize(3 * info_.triangle_count);
    dfm_mesh_read_indices(mesh_, indices_.data(), indices_.size());
    read_copies();
    reload_rest_pose();
    const dfm_vec3_input positions = {display_.data(), info_.vertex_count, 0, DFM_SCALAR_FLOAT32};
    dfm_camera start = {};
    if (!report(
            dfm_vk_renderer_set_mesh(renderer_, &positions, indices_.data(), info_.triangle_count),
            "dfm_vk_renderer_set_mesh") ||
        !report(dfm_vk_framing_camera(&positions, static_cast<std::uint32_t>(width),
                                      static_cast<std::uint32_t>(height), &start),
                "dfm_vk_framing_camera")) {
        return false;
    }
    camera_.reset(start);
    camera_.set_viewport(width, height);
    display_changed_ = false;
    return true;
}

bool Editor::reopen(const std::string& mesh_spec) {
    dfm_mesh* next = nullptr;
    if (!report(dfm_mesh_load(context_, mesh_spec.c_str(), &next), "dfm_mesh_load")) return false;
    cancel_selection();
    dfm_mesh_destroy(mesh_);
    mesh_ = nullptr;
    bakes_ = 0;
    const dfm_camera view = camera_.camera();
    return open_loaded(next, mesh_spec, static_cast<int>(view.width),
                       static_cast<int>(view.height));
}

void Editor::read_copies() {
    const std::size_t n = info_.vertex_count;
    lowest_copy_.resize(n);
    dfm_mesh_read_surface_map(mesh_, lowest_copy_.data(), n);
    copy_begin_.assign(n + 1, 0);
    for (std::uint32_t v : lowest_copy_) ++copy_begin_[v + 1];
    for (std::size_t v = 0; v < n; ++v) copy_begin_[v + 1] += copy_begin_[v];
    copies_.resize(n);
    std::vector<std::uint32_t> fill(copy_begin_.begin(), copy_begin_.end() - 1);
    for (std::uint32_t v = 0; v < n; ++v) copies_[fill[lowest_copy_[v]]++] = v;
}

void Editor::reload_rest_pose() {
    dfm_mesh_get_info(mesh_, &info_);
    rest_.resize(3 * info_.vertex_count);
    const dfm_vec3_output out = {rest_.data(), info_.vertex_count, 0, DFM_SCALAR_FLOAT32};
    dfm_mesh_read_positions(mesh_, &out);
    display_ = rest_;
    display_changed_ = true;
}

void Editor::resize(int width, int height) {
    camera_.set_viewport(width, height);
}

dfm_vk_frame Editor::frame() const {
    dfm_vk_frame f = {};
    f.camera = camera_.camera();
    f.flags = flags_;
    return f;
}

void Editor::press(Button button, double x, double y, bool shift) {
    last_x_ = press_x_ = x;
    last_y_ = press_y_ = y;
    moved_ = false;
    if (button == Button::right) orbiting_ = true;
    if (button == Button::middle) panning_ = true;
    if (button == Button::left) {
        left_down_ = true;
        if (stage_ == Stage::handles) begin_drag(x, y, shift);
    }
}

void Editor::release(Button button, double x, double y) {
    move(x, y);
    if (button == Button::right) orbiting_ = false;
    if (button == Button::middle) panning_ = false;
    if (button != Button::left || !left_down_) return;
    left_down_ = false;
    const bool was_drag = dragged_group_ >= 0 && moved_;
    dragged_group_ = -1;
    if (!was_drag) click(x, y);
}

void Editor::move(double x, double y) {
    const double dx = x - last_x_, dy = y - last_y_;
    if (std::abs(x - press_x_) + std::abs(y - press_y_) > 2.0) moved_ = true;
    if (orbiting_) camera_.orbit(dx, dy);
    if (panning_) camera_.pan(dx, dy);
    if (left_down_ && dragged_group_ >= 0 && moved_) drag_to(x, y);
    last_x_ = x;
    last_y_ = y;
}

void Editor::scroll(double steps) {
    camera_.zoom(steps);
}

void Editor::click(double x, double y) {
    switch (stage_) {
        case Stage::pick_first:
        case Stage::pick_last: pick_endpoint(x, y); break;
        case Stage::suspect: break;
        case Stage::handles: add_handle(x, y); break;
    }
}

void Editor::pick_endpoint(double x, double y) {
    const dfm_camera camera = camera_.camera();
    dfm_hit hit = {};
    if (!report(dfm_mesh_pick(mesh_, &camera, x, y, &hit), "dfm_mesh_pick") || !hit.hit) return;
    if (stage_ == Stage::pick_first) {
        first_ = hit.vertex;
        stage_ = Stage::pick_last;
        refresh_lines();
        return;
    }
    last_ = hit.vertex;
    dfm_roi* roi = nullptr;
    if (!report(dfm_roi_water_fill(mesh_, first_, last_, &roi, &diagnosis_),
                "dfm_roi_water_fill")) {
        stage_ = Stage::pick_first;
        refresh_lines();
        return;
    }
    roi_ = roi;
    std::size_t n = 0;
    dfm_roi_count(roi_, &n);
    roi_vertices_.resize(n);
    dfm_roi_read(roi_, roi_vertices_.data(), n);
    stage_ = diagnosis_.suspect ? Stage::suspect : Stage::handles;
    refresh_marks();
    refresh_lines();
}

void Editor::add_handle(double x, double y) {
    const dfm_camera camera = camera_.camera();
    dfm_hit hit = {};
    if (!report(dfm_mesh_pick(mesh_, &camera, x, y, &hit), "dfm_mesh_pick") || !hit.hit) return;
    if (!std::binary_search(roi_vertices_.begin(), roi_vertices_.end(), hit.vertex)) return;
    for (const auto& group : groups_) {
        if (std::find(group.begin(), group.end(), hit.vertex) != group.end()) return;
    }
    dfm_roi* ball = nullptr;
    if (!report(dfm_roi_ball(mesh_, hit.vertex, handle_radius_, &ball), "dfm_roi_ball")) return;
    std::size_t n = 0;
    dfm_roi_count(ball, &n);
    std::vector<std::uint32_t> vertices(n);
    dfm_roi_read(ball, vertices.data(), n);
    dfm_roi_destroy(ball);
    // Only ROI vertices can be handles, and each in one group.
    std::erase_if(vertices, [&](std::uint32_t v) {
        if (!std::binary_search(roi_vertices_.begin(), roi_vertices_.end(), v)) return true;
        for (const auto& group : groups_) {
            if (std::find(group.begin(), group.end(), v) != group.end()) return true;
        }
        return false;
    });
    if (vertices.empty()) return;
    end_session();
    groups_.push_back(std::move(vertices));
    transforms_.assign(groups_.size(), identity());
    refresh_marks();
}

Vec3 Editor::group_centroid(std::size_t group) const {
    Vec3 sum{0, 0, 0};
    for (std::uint32_t v : groups_[group]) {
        const Vec3 rest = {rest_[3 * v], rest_[3 * v + 1], rest_[3 * v + 2]};
        const Vec3 p = apply(transforms_[group], rest);
        for (int c = 0; c < 3; ++c) sum[c] += p[c];
    }
    const double n = static_cast<double>(groups_[group].size());
    return {sum[0] / n, sum[1] / n, sum[2] / n};
}

void Editor::begin_drag(double x, double y, bool rotate) {
    // The group whose (moved) centre is nearest the pointer, within 40 px.
    double best = 40.0;
    dragged_group_ = -1;
    for (std::size_t g = 0; g < groups_.size(); ++g) {
        double px = 0, py = 0;
        if (!camera_.project(group_centroid(g), px, py)) continue;
        const double d = std::hypot(px - x, py - y);
        if (d < best) best = d, dragged_group_ = static_cast<int>(g);
    }
    rotating_ = rotate;
}

void Editor::drag_to(double x, double y) {
    if (!ensure_session()) {
        dragged_group_ = -1;
        return;
    }
    const std::size_t g = static_cast<std::size_t>(dragged_group_);
    const Vec3 centre = group_centroid(g);
    const double dx = x - last_x_, dy = y - last_y_;
    Matrix step;
    if (rotating_) {
        // Half a degree per pixel, about the view axis through the centre.
        step = multiply(translation(centre),
                        multiply(rotation(camera_.forward(), dx * 0.5 * pi / 180.0),
                                 translation({-centre[0], -centre[1], -centre[2]})));
    } else {
        step = translation(camera_.drag_in_view_plane(centre, dx, dy));
    }
    transforms_[g] = multiply(step, transforms_[g]);
    transforms_dirty_ = true;
}

bool Editor::ensure_session() {
    if (session_ != nullptr) return true;
    std::vector<dfm_handle_group> groups;
    for (const auto& group : groups_) groups.push_back({group.data(), group.size()});
    dfm_session_desc desc = {};
    desc.roi = roi_;
    desc.groups = groups.data();
    desc.group_count = groups.size();
    desc.solver = solver_;
    if (!report(dfm_session_create(mesh_, &desc, &session_), "dfm_session_create")) return false;
    submitted_ = shown_ = 0;
    transforms_dirty_ = true;
    return true;
}

void Editor::end_session() {
    dfm_session_destroy(session_);
    session_ = nullptr;
    submitted_ = shown_ = 0;
    last_info_ = dfm_frame_info{};
}

void Editor::cancel_selection() {
    end_session();
    dfm_roi_destroy(roi_);
    roi_ = nullptr;
    roi_vertices_.clear();
    groups_.clear();
    transforms_.clear();
    diagnosis_ = {};
    stage_ = Stage::pick_first;
    display_ = rest_;
    display_changed_ = true;
    refresh_marks();
    refresh_lines();
}

void Editor::reset_transforms() {
    transforms_.assign(groups_.size(), identity());
    transforms_dirty_ = session_ != nullptr;
}

void Editor::bake() {
    if (session_ == nullptr) return;
    if (!report(dfm_session_bake(session_), "dfm_session_bake")) return;
    ++bakes_;
    // The session restarted on the baked pose with identity transforms.
    transforms_.assign(groups_.size(), identity());
    transforms_dirty_ = false;
    reload_rest_pose();
    refresh_lines();
}

void Editor::undo_or_redo(bool undo) {
    // A session belongs to the rest pose it started on.
    end_session();
    const dfm_result r = undo ? dfm_mesh_undo_bake(mesh_) : dfm_mesh_redo_bake(mesh_);
    if (r == DFM_ERROR_NOT_FOUND) return;
    if (!report(r, undo ? "dfm_mesh_undo_bake" : "dfm_mesh_redo_bake")) return;
    bakes_ = undo ? bakes_ - std::min<std::size_t>(bakes_, 1) : bakes_ + 1;
    transforms_.assign(groups_.size(), identity());
    reload_rest_pose();
    refresh_lines();
}

void Editor::key(const std::string& name) {
    if (name == "escape") {
        cancel_selection();
    } else if (name == "enter") {
        if (stage_ == Stage::suspect) stage_ = Stage::handles;
    } else if (name == "b") {
        bake();
    } else if (name == "ctrl+z") {
        undo_or_redo(true);
    } else if (name == "ctrl+y") {
        undo_or_redo(false);
    } else if (name == "r" || name == "backspace") {
        reset_transforms();
    } else if (name == "e") {
        save_scenario("viewer_edit.json");
    } else if (name == "w") {
        flags_ ^= DFM_VK_FLAG_WIREFRAME;
    } else if (name == "f") {
        flags_ ^= DFM_VK_FLAG_FLAT;
    } else if (name == "[") {
        handle_radius_ = std::max(0.005, handle_radius_ / 1.25);
    } else if (name == "]") {
        handle_radius_ = std::min(0.3, handle_radius_ * 1.25);
    } else if (name == "q") {
        quit_ = true;
    }
}

bool Editor::update() {
    if (session_ != nullptr && transforms_dirty_) {
        for (std::size_t g = 0; g < transforms_.size(); ++g) {
            if (!report(dfm_session_set_group_transform(session_, static_cast<std::uint32_t>(g),
                                                        transforms_[g].data()),
                        "dfm_session_set_group_transform")) {
                return false;
            }
        }
        if (!report(dfm_session_submit(session_, &submitted_), "dfm_session_submit")) return false;
        transforms_dirty_ = false;
    }
    if (session_ != nullptr) {
        bool is_new = false;
        dfm_frame_info info = {};
        dfm_session_poll(session_, shown_, &info, &is_new);
        dfm_frame_view view = {};
        if (is_new && dfm_session_acquire_frame(session_, &view, &info) == DFM_OK) {
            // One entry per surface vertex, named by its lowest copy: every
            // copy of it moves, so no seam opens.
            for (std::size_t i = 0; i < view.roi_count; ++i) {
                const std::uint32_t v = view.roi_vertices[i];
                for (std::uint32_t k = copy_begin_[v]; k < copy_begin_[v + 1]; ++k) {
                    for (int c = 0; c < 3; ++c) {
                        display_[3 * copies_[k] + c] = view.roi_positions[3 * i + c];
                    }
                }
            }
            dfm_session_release_frame(session_);
            shown_ = info.generation;
            last_info_ = info;
            display_changed_ = true;
        }
    }
    if (display_changed_) {
        const dfm_vec3_input positions = {display_.data(), info_.vertex_count, 0,
                                          DFM_SCALAR_FLOAT32};
        if (!report(dfm_vk_renderer_update_positions(renderer_, &positions),
                    "dfm_vk_renderer_update_positions")) {
            return false;
        }
        display_changed_ = false;
    }
    return true;
}

bool Editor::settled() const {
    if (session_ == nullptr) return true;
    if (transforms_dirty_) return false;
    return shown_ >= submitted_ && !last_info_.partial;
}

void Editor::refresh_marks() {
    std::vector<std::uint8_t> marks(info_.vertex_count, DFM_VK_MARK_SURFACE);
    for (std::uint32_t v : roi_vertices_) marks[v] = DFM_VK_MARK_ROI;
    for (const auto& group : groups_) {
        for (std::uint32_t v : group) marks[v] = DFM_VK_MARK_HANDLE;
    }
    for (std::size_t v = 0; v < marks.size(); ++v) marks[v] = marks[lowest_copy_[v]];
    report(dfm_vk_renderer_set_marks(renderer_, marks.data(), marks.size()),
           "dfm_vk_renderer_set_marks");
}

void Editor::refresh_lines() {
    if (stage_ == Stage::pick_first) {
        report(dfm_vk_renderer_set_lines(renderer_, nullptr, 0), "dfm_vk_renderer_set_lines");
        return;
    }
    // The region line from the first click's vertex to the last's (red for a
    // suspect region), and once the region is filled, the cutting plane's
    // loop: where the plane through `last`, normal to the region line, cuts
    // the triangles that touch the region.
    const std::uint32_t end = stage_ == Stage::pick_last ? first_ : last_;
    std::vector<float> points = {rest_[3 * first_], rest_[3 * first_ + 1], rest_[3 * first_ + 2],
                                 rest_[3 * end],    rest_[3 * end + 1],    rest_[3 * end + 2]};
    std::vector<dfm_vk_polyline> lines(1);
    if (diagnosis_.suspect) {
        lines[0].color[0] = 1.0f;
        lines[0].color[3] = 1.0f;
    }
    if (roi_ != nullptr) {
        const Vec3 at = {rest_[3 * last_], rest_[3 * last_ + 1], rest_[3 * last_ + 2]};
        const Vec3 normal = {at[0] - points[0], at[1] - points[1], at[2] - points[2]};
        const auto side = [&](std::uint32_t v) {
            double d = 0.0;
            for (int c = 0; c < 3; ++c) d += (rest_[3 * v + c] - at[c]) * normal[c];
            return d;
        };
        for (std::size_t t = 0; t < info_.triangle_count; ++t) {
            const std::uint32_t* tri = &indices_[3 * t];
            const auto in_roi = [&](std::uint32_t v) {
                return std::binary_search(roi_vertices_.begin(), roi_vertices_.end(),
                                          lowest_copy_[v]);
            };
            if (!in_roi(tri[0]) && !in_roi(tri[1]) && !in_roi(tri[2])) continue;
            std::size_t crossings = 0;
            for (int e = 0; e < 3; ++e) {
                const std::uint32_t a = tri[e], b = tri[(e + 1) % 3];
                const double da = side(a), db = side(b);
                if ((da < 0.0) == (db < 0.0)) continue;
                const double u = da / (da - db);
                for (int c = 0; c < 3; ++c) {
                    points.push_back(static_cast<float>(rest_[3 * a + c] +
                                                        u * (rest_[3 * b + c] - rest_[3 * a + c])));
                }
                ++crossings;
            }
            // A plane crosses a triangle's edges twice or not at all.
            if (crossings != 2) points.resize(points.size() - 3 * crossings);
        }
    }
    // The points vector is complete now: take the pointers.
    lines[0].points = {points.data(), 2, 0, DFM_SCALAR_FLOAT32};
    for (std::size_t first = 6; first + 6 <= points.size(); first += 6) {
        dfm_vk_polyline segment = {};
        segment.points = {&points[first], 2, 0, DFM_SCALAR_FLOAT32};
        segment.color[1] = segment.color[2] = 1.0f;
        segment.color[3] = 1.0f;
        lines.push_back(segment);
    }
    report(dfm_vk_renderer_set_lines(renderer_, lines.data(), lines.size()),
           "dfm_vk_renderer_set_lines");
}

std::string Editor::status_line() const {
    char text[256];
    const char* what = "";
    switch (stage_) {
        case Stage::pick_first: what = "click the limb's tip"; break;
        case Stage::pick_last: what = "click where the region ends"; break;
        case Stage::suspect: what = "SUSPECT region: Enter keeps it, Escape cancels"; break;
        case Stage::handles:
            what = groups_.empty() ? "click handles" : "drag handles (shift: rotate)";
            break;
    }
    std::snprintf(text, sizeof text,
                  "Dualform | ROI %zu (%zu loops) | %zu handles | gen %llu: %u iterations, %.2f "
                  "ms%s | %s",
                  roi_vertices_.size(), diagnosis_.loops, groups_.size(),
                  static_cast<unsigned long long>(last_info_.generation), last_info_.iterations,
                  last_info_.solve_ms, last_info_.partial ? " (preview)" : "", what);
    return text;
}

bool Editor::write_screenshot(const std::string& path) {
    const dfm_vk_frame f = frame();
    std::vector<std::uint8_t> rgba(static_cast<std::size_t>(f.camera.width) * f.camera.height * 4);
    return report(dfm_vk_renderer_render_offscreen(renderer_, &f, rgba.data(), rgba.size()),
                  "dfm_vk_renderer_render_offscreen") &&
           report(dfm_vk_write_png(path.c_str(), rgba.data(), rgba.size(), f.camera.width,
                                   f.camera.height),
                  "dfm_vk_write_png");
}

bool Editor::has_unbaked_edit() const {
    if (session_ == nullptr) return false;
    return std::any_of(transforms_.begin(), transforms_.end(),
                       [](const Matrix& m) { return m != identity(); });
}

bool Editor::save_mesh(const std::string& path, const std::string& morph_target) {
    if (has_unbaked_edit()) bake();
    dfm_save_options options = {};
    options.struct_size = sizeof options;
    options.morph_target_name = morph_target.empty() ? nullptr : morph_target.c_str();
    return report(dfm_mesh_save_with_options(mesh_, path.c_str(), &options),
                  "dfm_mesh_save_with_options");
}

bool Editor::set_solver(const dfm_solver_settings& settings) {
    if (settings.tolerance <= 0.0 || !std::isfinite(settings.tolerance) ||
        settings.max_iterations == 0 || settings.handle_weight <= 0.0 ||
        !std::isfinite(settings.handle_weight)) {
        last_error_ = "solver: the tolerance, iteration cap and handle weight must be positive";
        return false;
    }
    const bool fixed_changed = settings.handle_weight != solver_.handle_weight ||
                               settings.hard_handles != solver_.hard_handles ||
                               settings.method != solver_.method;
    const dfm_solver_settings previous = solver_;
    solver_ = settings;
    if (session_ == nullptr) return true;
    if (fixed_changed) {
        // Fixed at creation: the same edit goes on in a new session.
        end_session();
        return ensure_session();
    }
    dfm_solver_settings change = {};
    change.tolerance = settings.tolerance;
    change.max_iterations = settings.max_iterations;
    if (!report(dfm_session_set_solver(session_, &change), "dfm_session_set_solver")) {
        solver_ = previous;
        return false;
    }
    // The shown frame met the old tolerance: solve the same targets again.
    transforms_dirty_ = true;
    return true;
}

bool Editor::solve_report(dfm_solve_report& out) const {
    out = {};
    if (session_ == nullptr) return false;
    return dfm_session_get_solve_report(session_, &out, nullptr) == DFM_OK;
}

namespace {

bool write_json(const std::string& path, const dfm::json::JsonWriter& json) {
    std::ofstream out(path);
    out << json.str() << '\n';
    out.close();
    if (!out) {
        std::fprintf(stderr, "viewer: could not write %s\n", path.c_str());
        return false;
    }
    return true;
}

}  // namespace

bool Editor::save_camera(const std::string& path) const {
    const dfm_camera c = camera_.camera();
    dfm::json::JsonWriter json(dfm::json::JsonWriter::Layout::indented);
    json.begin_object();
    json.key("eye").numbers(c.eye, 3);
    json.key("target").numbers(c.target, 3);
    json.key("up").numbers(c.up, 3);
    json.field("fov_y_degrees", c.fov_y_degrees);
    json.field("width", c.width);
    json.field("height", c.height);
    json.end_object();
    return write_json(path, json);
}

bool Editor::save_scenario(const std::string& path) const {
    if (roi_ == nullptr || groups_.empty()) {
        std::fprintf(stderr, "viewer: no edit to save yet (select a region and handles)\n");
        return false;
    }
    dfm::json::JsonWriter json(dfm::json::JsonWriter::Layout::indented);
    json.begin_object();
    json.field("description", "saved by the Dualform viewer");
    json.field("mesh", mesh_spec_);
    json.key("solver").begin_object();
    json.field("tolerance", solver_.tolerance);
    json.field("max_iterations", solver_.max_iterations);
    json.field("handle_weight", solver_.handle_weight);
    json.field("method", solver_.method == DFM_METHOD_PAPER ? "paper" : "fitted_rotations");
    json.end_object();
    json.key("roi").begin_object().key("water_fill").begin_object();
    json.field("first", first_).field("last", last_);
    json.end_object().end_object();
    json.key("handles").begin_array();
    for (std::size_t g = 0; g < groups_.size(); ++g) {
        json.begin_object();
        json.key("vertices").numbers(groups_[g].data(), groups_[g].size());
        json.key("targets").begin_array();
        for (const std::uint32_t v : groups_[g]) {
            const Vec3 p =
                apply(transforms_[g], {rest_[3 * v], rest_[3 * v + 1], rest_[3 * v + 2]});
            json.numbers(p.data(), 3);
        }
        json.end_array().end_object();
    }
    json.end_array().end_object();
    return write_json(path, json);
}

}  // namespace viewer
