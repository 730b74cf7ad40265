#include <doctest/doctest.h>

#include <algorithm>
#include <cstring>
#include <vector>

#include "dualform/dualform.h"
#include "sdk/sdk_fixture.hpp"
#include "support/gltf_builder.hpp"
#include "support/procedural_meshes.hpp"

using namespace dfm;

namespace {

dfm_mesh* create(dfm_context* context, const std::vector<double>& xyz,
                 const std::vector<mesh::Triangle>& triangles, dfm_weld_mode weld) {
    dfm_mesh_desc desc = {};
    desc.struct_size = sizeof desc;
    desc.positions.data = xyz.data();
    desc.positions.count = xyz.size() / 3;
    desc.positions.type = DFM_SCALAR_FLOAT64;
    desc.indices = triangles.front().data();
    desc.triangle_count = triangles.size();
    desc.weld = weld;
    dfm_mesh* out = nullptr;
    REQUIRE_MESSAGE(dfm_mesh_create(context, &desc, &out) == DFM_OK, test::last_error());
    return out;
}

std::vector<double> flat(const std::vector<glm::dvec3>& p) {
    std::vector<double> out;
    for (const auto& v : p) out.insert(out.end(), {v.x, v.y, v.z});
    return out;
}

// The limb edit (ROI above y = 0.5, the tip moved) on `mesh`; the ROI and
// the tip as vertex lists of that mesh. Returns the solved positions.
std::vector<double> edit(dfm_mesh* mesh, const std::vector<std::uint32_t>& region,
                         const std::vector<std::uint32_t>& tip,
                         std::vector<std::uint32_t>& roi_read,
                         std::vector<std::uint32_t>& view_roi) {
    dfm_roi* roi = nullptr;
    REQUIRE(dfm_roi_from_vertices(mesh, region.data(), region.size(), &roi) == DFM_OK);
    size_t n = 0;
    REQUIRE(dfm_roi_count(roi, &n) == DFM_OK);
    roi_read.resize(n);
    REQUIRE(dfm_roi_read(roi, roi_read.data(), n) == DFM_OK);
    const dfm_handle_group group = {tip.data(), tip.size()};
    dfm_session_desc desc = {};
    desc.roi = roi;
    desc.groups = &group;
    desc.group_count = 1;
    dfm_session* session = nullptr;
    REQUIRE_MESSAGE(dfm_session_create(mesh, &desc, &session) == DFM_OK, test::last_error());
    double m[16];
    test::translation(0.4, -0.1, 0.2, m);
    REQUIRE(dfm_session_set_group_transform(session, 0, m) == DFM_OK);
    REQUIRE(dfm_session_solve(session, nullptr) == DFM_OK);
    dfm_mesh_info info = {};
    REQUIRE(dfm_mesh_get_info(mesh, &info) == DFM_OK);
    std::vector<double> out(3 * info.vertex_count);
    dfm_vec3_output o = {};
    o.data = out.data();
    o.count = info.vertex_count;
    o.type = DFM_SCALAR_FLOAT64;
    REQUIRE(dfm_session_read_positions(session, &o, nullptr) == DFM_OK);
    dfm_frame_view view = {};
    REQUIRE(dfm_session_acquire_frame(session, &view, nullptr) == DFM_OK);
    view_roi.assign(view.roi_vertices, view.roi_vertices + view.roi_count);
    REQUIRE(dfm_session_release_frame(session) == DFM_OK);
    dfm_session_destroy(session);
    dfm_roi_destroy(roi);
    return out;
}

}  // namespace

TEST_CASE(
    "host numbering: seam-split buffers welded, the edit moves every copy alike and "
    "equals the same edit on the welded mesh") {
    const mesh::Mesh limb = test::make_limb(16, 20, 0.2, 2.0);
    const mesh::Mesh split = test::split_corners(limb, [](std::size_t t) { return t % 3 == 0; });
    dfm_context* context = nullptr;
    REQUIRE(dfm_context_create(nullptr, &context) == DFM_OK);
    dfm_mesh* host = create(context, flat(split.positions), split.triangles, DFM_WELD_EXACT);

    dfm_mesh_info info = {};
    REQUIRE(dfm_mesh_get_info(host, &info) == DFM_OK);
    CHECK(info.vertex_count == split.vertex_count());
    CHECK(info.surface_vertex_count == limb.vertex_count());
    CHECK(info.boundary_edges == 0);
    std::vector<std::uint32_t> lowest(split.vertex_count());
    REQUIRE(dfm_mesh_read_surface_map(host, lowest.data(), lowest.size()) == DFM_OK);
    std::vector<std::uint32_t> indices(3 * split.face_count());
    REQUIRE(dfm_mesh_read_indices(host, indices.data(), indices.size()) == DFM_OK);
    CHECK(std::memcmp(indices.data(), split.triangles.data(), indices.size() * 4) == 0);

    // The welded mesh: surface vertex s is the s-th lowest copy.
    std::vector<std::uint32_t> firsts;
    for (std::uint32_t h = 0; h < lowest.size(); ++h) {
        if (lowest[h] == h) firsts.push_back(h);
    }
    REQUIRE(firsts.size() == limb.vertex_count());
    const auto surface_of = [&](std::uint32_t h) {
        return static_cast<std::uint32_t>(
            std::lower_bound(firsts.begin(), firsts.end(), lowest[h]) - firsts.begin());
    };
    std::vector<glm::dvec3> welded_positions;
    for (std::uint32_t h : firsts) welded_positions.push_back(split.positions[h]);
    std::vector<mesh::Triangle> welded_triangles;
    for (const auto& t : split.triangles) {
        welded_triangles.push_back({surface_of(t[0]), surface_of(t[1]), surface_of(t[2])});
    }
    dfm_mesh* welded = create(context, flat(welded_positions), welded_triangles, DFM_WELD_NONE);

    // The host names its vertices by any copy: the whole ROI with every
    // copy, the tip by copies that are not the lowest where there are any.
    std::vector<std::uint32_t> host_region, host_tip, surface_region, surface_tip;
    std::vector<bool> tip_taken(limb.vertex_count(), false);
    for (std::uint32_t h = static_cast<std::uint32_t>(split.vertex_count()); h-- > 0;) {
        const glm::dvec3 p = split.positions[h];
        if (p.y > 0.5) host_region.push_back(h);
        if (p.y >= 1.8 && !tip_taken[surface_of(h)]) {
            tip_taken[surface_of(h)] = true;
            host_tip.push_back(h);
        }
    }
    std::sort(host_tip.begin(), host_tip.end(),
              [&](std::uint32_t a, std::uint32_t b) { return lowest[a] < lowest[b]; });
    for (std::uint32_t h : host_tip) surface_tip.push_back(surface_of(h));
    for (std::uint32_t s = 0; s < welded_positions.size(); ++s) {
        if (welded_positions[s].y > 0.5) surface_region.push_back(s);
    }
    CHECK(std::any_of(host_tip.begin(), host_tip.end(),
                      [&](std::uint32_t h) { return lowest[h] != h; }));

    std::vector<std::uint32_t> host_roi, surface_roi, host_view, surface_view;
    const std::vector<double> a = edit(host, host_region, host_tip, host_roi, host_view);
    const std::vector<double> b =
        edit(welded, surface_region, surface_tip, surface_roi, surface_view);
    REQUIRE(host_roi.size() == surface_roi.size());
    for (std::size_t i = 0; i < host_roi.size(); ++i) {
        CHECK(host_roi[i] == firsts[surface_roi[i]]);
        CHECK(host_view[i] == firsts[surface_view[i]]);
    }
    bool moved = false;
    for (std::uint32_t h = 0; h < split.vertex_count(); ++h) {
        const std::uint32_t s = surface_of(h);
        // Bit for bit: every copy as its lowest copy, and as the welded mesh.
        CHECK(std::memcmp(&a[3 * h], &a[3 * lowest[h]], 24) == 0);
        CHECK(std::memcmp(&a[3 * h], &b[3 * s], 24) == 0);
        if (a[3 * h] != split.positions[h].x) moved = true;
    }
    CHECK(moved);

    dfm_mesh_destroy(welded);
    dfm_mesh_destroy(host);
    dfm_context_destroy(context);
}

TEST_CASE("host numbering: vertex indices out of the host's range are located errors") {
    const mesh::Mesh limb = test::make_limb(8, 4, 0.2, 2.0);
    const mesh::Mesh split = test::split_corners(limb, [](std::size_t t) { return t % 2 == 0; });
    dfm_context* context = nullptr;
    REQUIRE(dfm_context_create(nullptr, &context) == DFM_OK);
    dfm_mesh* host = create(context, flat(split.positions), split.triangles, DFM_WELD_EXACT);
    const auto n = static_cast<std::uint32_t>(split.vertex_count());
    dfm_roi* roi = nullptr;
    CHECK(dfm_roi_ball(host, n, 0.1, &roi) == DFM_ERROR_OUT_OF_RANGE);
    CHECK(test::message_has("center: vertex"));
    const std::uint32_t list[2] = {0, n + 3};
    CHECK(dfm_roi_from_vertices(host, list, 2, &roi) == DFM_ERROR_OUT_OF_RANGE);
    CHECK(test::message_has("vertices entry 1: vertex"));
    CHECK(dfm_roi_water_fill(host, 0, n, &roi, nullptr) == DFM_ERROR_OUT_OF_RANGE);
    CHECK(test::message_has("last: vertex"));
    dfm_mesh* fine = nullptr;
    CHECK(dfm_mesh_subdivide(host, 1, &fine) == DFM_ERROR_UNSUPPORTED);

    dfm_mesh_desc desc = {};
    desc.struct_size = sizeof desc;
    const std::vector<double> xyz = flat(split.positions);
    desc.positions.data = xyz.data();
    desc.positions.count = split.vertex_count();
    desc.positions.type = DFM_SCALAR_FLOAT64;
    desc.indices = split.triangles.front().data();
    desc.triangle_count = split.face_count();
    desc.weld = DFM_WELD_TOLERANCE;
    dfm_mesh* bad = nullptr;
    CHECK(dfm_mesh_create(context, &desc, &bad) == DFM_ERROR_INVALID_ARGUMENT);
    CHECK(test::message_has("weld_tolerance"));
    desc.weld_tolerance = 1e-9;
    REQUIRE(dfm_mesh_create(context, &desc, &bad) == DFM_OK);
    dfm_mesh_info info = {};
    REQUIRE(dfm_mesh_get_info(bad, &info) == DFM_OK);
    CHECK(info.surface_vertex_count == limb.vertex_count());
    dfm_mesh_destroy(bad);
    dfm_mesh_destroy(host);
    dfm_context_destroy(context);
}
