#include "rig.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace game {

namespace {

constexpr double pi = 3.14159265358979323846;

bool ok(dfm_result result, const char* call) {
    if (result == DFM_OK) return true;
    std::fprintf(stderr, "game_loop: %s: %s: %s\n", call, dfm_result_name(result),
                 dfm_last_error_message());
    return false;
}

// One session: the ROI, and a ball of `handle_radius` diagonals around
// `handle_centre` as its single handle group.
bool make_rig(dfm_mesh* mesh, const char* name, Motion motion, dfm_roi* roi,
              std::uint32_t handle_centre, double handle_radius, Rig& out) {
    out.name = name;
    out.motion = motion;
    out.roi = roi;
    dfm_roi* handle = nullptr;
    if (!ok(dfm_roi_ball(mesh, handle_centre, handle_radius, &handle), "dfm_roi_ball")) {
        return false;
    }
    std::size_t count = 0;
    dfm_roi_count(handle, &count);
    std::vector<std::uint32_t> vertices(count);
    const bool read = ok(dfm_roi_read(handle, vertices.data(), count), "dfm_roi_read");
    dfm_roi_destroy(handle);
    if (!read) return false;
    const dfm_handle_group group = {vertices.data(), vertices.size()};
    dfm_session_desc desc = {};
    desc.roi = roi;
    desc.groups = &group;
    desc.group_count = 1;
    return ok(dfm_session_create(mesh, &desc, &out.session), "dfm_session_create");
}

bool water_fill(dfm_mesh* mesh, std::uint32_t first, std::uint32_t last, dfm_roi** out) {
    dfm_water_fill_diagnosis diagnosis = {};
    if (!ok(dfm_roi_water_fill(mesh, first, last, out, &diagnosis), "dfm_roi_water_fill")) {
        return false;
    }
    if (diagnosis.suspect) {
        std::fprintf(stderr, "game_loop: the region %u -> %u looks wrong (%zu loops)\n", first,
                     last, diagnosis.loops);
        return false;
    }
    return true;
}

// The vertex farthest from the bounding box's centre: an extremity to wave.
std::uint32_t farthest_vertex(dfm_mesh* mesh, const dfm_mesh_info& info) {
    std::vector<double> xyz(3 * info.vertex_count);
    const dfm_vec3_output out = {xyz.data(), info.vertex_count, 0, DFM_SCALAR_FLOAT64};
    dfm_mesh_read_positions(mesh, &out);
    double best = -1.0;
    std::uint32_t best_vertex = 0;
    for (std::size_t v = 0; v < info.vertex_count; ++v) {
        double d = 0.0;
        for (int c = 0; c < 3; ++c) {
            const double centre = 0.5 * (info.bounds_min[c] + info.bounds_max[c]);
            d += (xyz[3 * v + c] - centre) * (xyz[3 * v + c] - centre);
        }
        if (d > best) best = d, best_vertex = static_cast<std::uint32_t>(v);
    }
    return best_vertex;
}

}  // namespace

bool make_rigs(dfm_mesh* mesh, const std::string& model, std::vector<Rig>& out) {
    out.clear();
    if (model == "model:cow" || model == "cow") {
        // Vertex numbers of the paper's cow: 2334 is the tail tip, 964 up the
        // tail below its root; 771 the front hoof, 681 above the knee.
        dfm_roi* tail = nullptr;
        dfm_roi* leg = nullptr;
        if (!water_fill(mesh, 2334, 964, &tail)) return false;
        out.emplace_back();
        if (!make_rig(mesh, "tail", Motion::shake, tail, 2334, 0.02, out.back())) return false;
        if (!water_fill(mesh, 771, 681, &leg)) return false;
        out.emplace_back();
        return make_rig(mesh, "front leg", Motion::step, leg, 771, 0.03, out.back());
    }
    dfm_mesh_info info = {};
    if (!ok(dfm_mesh_get_info(mesh, &info), "dfm_mesh_get_info")) return false;
    const std::uint32_t tip = farthest_vertex(mesh, info);
    dfm_roi* region = nullptr;
    if (!ok(dfm_roi_ball(mesh, tip, 0.15, &region), "dfm_roi_ball")) return false;
    out.emplace_back();
    return make_rig(mesh, "extremity", Motion::wave, region, tip, 0.02, out.back());
}

void transform_at(Motion motion, double t, double diagonal, double out[16]) {
    for (int i = 0; i < 16; ++i) out[i] = (i % 5 == 0) ? 1.0 : 0.0;
    switch (motion) {
        case Motion::shake:  // side to side at 2 Hz, a flick up at 4 Hz
            out[14] = 0.06 * diagonal * std::sin(2.0 * pi * 2.0 * t);
            out[13] = 0.02 * diagonal * std::sin(2.0 * pi * 4.0 * t);
            break;
        case Motion::step:  // forward and back at 0.75 Hz, lifted on the way out
            out[12] = 0.06 * diagonal * (0.5 - 0.5 * std::cos(2.0 * pi * 0.75 * t));
            out[13] = 0.03 * diagonal * std::max(0.0, std::sin(2.0 * pi * 0.75 * t));
            break;
        case Motion::wave:
            out[12] = 0.04 * diagonal * std::sin(2.0 * pi * 1.0 * t);
            out[13] = 0.04 * diagonal * std::sin(2.0 * pi * 0.5 * t);
            break;
    }
}

void destroy_rigs(std::vector<Rig>& rigs) {
    for (Rig& rig : rigs) {
        dfm_session_destroy(rig.session);
        dfm_roi_destroy(rig.roi);
    }
    rigs.clear();
}

}  // namespace game
