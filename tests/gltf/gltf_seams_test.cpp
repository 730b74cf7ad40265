// Issue 15, "done when" 1: a glTF that Blender exported with UV seams loads
// through the C API, two vertices, or two clicks through a camera, select a
// limb by Water-Filling (the same limb as on the welded OFF), the edit
// leaves no crack at any seam (every split copy of a surface vertex lands at
// the same position) and equals the same edit of the welded OFF surface.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <string>
#include <utility>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include "gltf_file.hpp"
#include "limb_edit.hpp"
#include "surface_match.hpp"
#include "third_party.hpp"

using namespace dfm::test::gltf;

namespace {

struct RoiPtr {
    dfm_roi* roi = nullptr;
    ~RoiPtr() { dfm_roi_destroy(roi); }
};

std::vector<std::uint32_t> read_triangles(const dfm_mesh* mesh) {
    dfm_mesh_info info{};
    REQUIRE(dfm_mesh_get_info(mesh, &info) == DFM_OK);
    std::vector<std::uint32_t> out(3 * info.triangle_count);
    REQUIRE(dfm_mesh_read_indices(mesh, out.data(), out.size()) == DFM_OK);
    return out;
}

MeshPtr create_welded(dfm_context* context, const Surface& s) {
    dfm_mesh_desc desc{};
    desc.struct_size = sizeof desc;
    desc.positions = {s.positions.data(), s.positions.size() / 3, 0, DFM_SCALAR_FLOAT64};
    desc.indices = s.triangles.data();
    desc.triangle_count = s.triangles.size() / 3;
    desc.weld = DFM_WELD_EXACT;
    dfm_mesh* m = nullptr;
    REQUIRE_MESSAGE(dfm_mesh_create(context, &desc, &m) == DFM_OK, dfm_last_error_message());
    return MeshPtr(m);
}

std::vector<std::uint32_t> roi_vertices(const dfm_roi* roi) {
    std::size_t n = 0;
    REQUIRE(dfm_roi_count(roi, &n) == DFM_OK);
    std::vector<std::uint32_t> out(n);
    REQUIRE(dfm_roi_read(roi, out.data(), n) == DFM_OK);
    return out;
}

// A camera looking at the limb from outside it (along `first`'s normal),
// and the pixels where it sees `first` and `last`.
struct Clicks {
    dfm_camera camera{};
    double first[2] = {};
    double last[2] = {};
};

glm::dvec3 vec(const double* p) {
    return {p[0], p[1], p[2]};
}

Clicks clicks_on(const dfm_mesh* welded, const std::vector<double>& rest, const LimbEdit& e) {
    dfm_mesh_info info{};
    REQUIRE(dfm_mesh_get_info(welded, &info) == DFM_OK);
    std::vector<double> normals(rest.size());
    const dfm_vec3_output o{normals.data(), info.vertex_count, 0, DFM_SCALAR_FLOAT64};
    REQUIRE(dfm_mesh_read_normals(welded, &o) == DFM_OK);
    const glm::dvec3 a = vec(rest.data() + 3 * e.first), b = vec(rest.data() + 3 * e.last);
    const glm::dvec3 target = 0.5 * (a + b);
    const glm::dvec3 eye =
        target + info.diagonal * glm::normalize(vec(normals.data() + 3 * e.first) +
                                                vec(normals.data() + 3 * e.last));
    const glm::dvec3 forward = glm::normalize(target - eye);
    const glm::dvec3 up = std::abs(forward.y) < 0.9 ? glm::dvec3(0, 1, 0) : glm::dvec3(1, 0, 0);
    Clicks c;
    c.camera = {
        {eye.x, eye.y, eye.z}, {target.x, target.y, target.z}, {up.x, up.y, up.z}, 30.0, 800, 600};
    const glm::dvec3 right = glm::normalize(glm::cross(forward, up));
    const glm::dvec3 image_up = glm::cross(right, forward);
    const double t = std::tan(glm::radians(15.0));
    for (auto [p, px] : {std::pair{a, c.first}, std::pair{b, c.last}}) {
        const glm::dvec3 d = p - eye;
        const double z = glm::dot(d, forward);
        px[0] = 400.0 * (1.0 + glm::dot(d, right) / (z * t * 800.0 / 600.0));
        px[1] = 300.0 * (1.0 - glm::dot(d, image_up) / (z * t));
    }
    return c;
}

const double* at(const std::vector<double>& p, std::uint32_t v) {
    return p.data() + 3 * v;
}

double distance(const double* a, const double* b) {
    return std::sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) +
                     (a[2] - b[2]) * (a[2] - b[2]));
}

// `edit` names vertices of the welded OFF surface; the glTF edit picks the
// split copies at the same positions.
void check_seamless_edit(const char* gltf_name, const char* off_name, const LimbEdit& edit) {
    CAPTURE(gltf_name);
    const ContextPtr context = make_context();
    const MeshPtr welded = load_mesh(context.get(), asset_path(off_name));
    const MeshPtr split = load_mesh(context.get(), asset_path(gltf_name));

    // The API keeps the file's vertices, in its order.
    const Asset asset = read_asset(asset_path(gltf_name));
    const std::size_t mesh = 0;
    const Surface file{mesh_positions(asset, mesh), mesh_triangles(asset, mesh)};
    const std::vector<double> rest = rest_positions(split.get());
    REQUIRE(rest == file.positions);
    const std::vector<double> welded_rest = rest_positions(welded.get());
    const std::vector<std::uint32_t> surface =
        match_surface(file, Surface{welded_rest, read_triangles(welded.get())});

    // The SDK's weld joins exactly the copies of one surface vertex: the
    // cow's two vertices at one position stay two.
    dfm_mesh_info info{};
    REQUIRE(dfm_mesh_get_info(split.get(), &info) == DFM_OK);
    CHECK(info.surface_vertex_count == welded_rest.size() / 3);
    std::vector<std::uint32_t> lowest(surface.size());
    REQUIRE(dfm_mesh_read_surface_map(split.get(), lowest.data(), lowest.size()) == DFM_OK);
    std::vector<std::uint32_t> lowest_of_surface(welded_rest.size() / 3, UINT32_MAX);
    std::size_t disagreements = 0;
    for (std::uint32_t v = 0; v < surface.size(); ++v) {
        std::uint32_t& l = lowest_of_surface[surface[v]];
        if (l == UINT32_MAX) l = v;
        if (lowest[v] != l) ++disagreements;
    }
    CHECK(disagreements == 0);

    LimbEdit split_edit = edit;
    split_edit.first = vertex_at(rest, at(welded_rest, edit.first));
    split_edit.last = vertex_at(rest, at(welded_rest, edit.last));
    split_edit.handle = vertex_at(rest, at(welded_rest, edit.handle));
    const EditOutcome expected = edit_limb(welded.get(), edit, false);
    const EditOutcome got = edit_limb(split.get(), split_edit, false);
    // A host handing the same split buffers with an exact weld gets the same.
    const MeshPtr host = create_welded(context.get(), file);
    const EditOutcome hosted = edit_limb(host.get(), split_edit, false);
    CHECK(hosted.roi == got.roi);

    // The same limb and handle, as surface vertices.
    std::set<std::uint32_t> roi, handles;
    for (std::uint32_t v : got.roi) roi.insert(surface[v]);
    for (std::uint32_t v : got.handles) handles.insert(surface[v]);
    CHECK(roi == std::set<std::uint32_t>(expected.roi.begin(), expected.roi.end()));
    CHECK(handles == std::set<std::uint32_t>(expected.handles.begin(), expected.handles.end()));

    // Two clicks select the same limb on either mesh.
    const Clicks clicks = clicks_on(welded.get(), welded_rest, edit);
    RoiPtr welded_click, split_click;
    REQUIRE(dfm_roi_water_fill_clicks(welded.get(), &clicks.camera, clicks.first, clicks.last,
                                      &welded_click.roi, nullptr) == DFM_OK);
    REQUIRE(dfm_roi_water_fill_clicks(split.get(), &clicks.camera, clicks.first, clicks.last,
                                      &split_click.roi, nullptr) == DFM_OK);
    CHECK(roi_vertices(welded_click.roi) == expected.roi);
    std::set<std::uint32_t> clicked;
    for (std::uint32_t v : roi_vertices(split_click.roi)) clicked.insert(surface[v]);
    CHECK(clicked == roi);

    // No crack: the copies of one surface vertex stay together.
    std::vector<std::uint32_t> first_copy(welded_rest.size() / 3, UINT32_MAX);
    std::size_t copies = 0, cracks = 0;
    for (std::uint32_t v = 0; v < surface.size(); ++v) {
        std::uint32_t& c = first_copy[surface[v]];
        if (c == UINT32_MAX) {
            c = v;
            continue;
        }
        ++copies;
        if (!std::equal(at(got.positions, v), at(got.positions, v) + 3, at(got.positions, c)))
            ++cracks;
    }
    CHECK(copies > 0);
    CHECK(cracks == 0);

    // The welded OFF's edit, vertex by vertex.
    const double d = diagonal(welded.get());
    double worst = 0.0, moved = 0.0;
    for (std::uint32_t v = 0; v < surface.size(); ++v) {
        worst = std::max(worst, distance(at(got.positions, v), at(expected.positions, surface[v])));
        moved = std::max(moved, distance(at(got.positions, v), at(rest, v)));
    }
    CHECK(worst <= 1e-9 * d);
    double host_worst = 0.0;
    for (std::uint32_t v = 0; v < surface.size(); ++v)
        host_worst = std::max(host_worst, distance(at(hosted.positions, v), at(got.positions, v)));
    CHECK(host_worst <= 1e-9 * d);
    CHECK(moved > 0.01 * d);
}

}  // namespace

TEST_CASE("seams: Blender's Suzanne, her ear edited, no crack, as the welded OFF") {
    // 7788: the tip of her left ear (largest x); 7857 where the ear meets the head.
    check_seamless_edit("suzanne.glb", "suzanne.off", {7788, 7857, 7788, 0.02, {0.0, 0.08, 0.0}});
}

TEST_CASE("seams: Blender's cow, split at every corner, its front leg stepped") {
    // tests/scenarios/cow-front-leg-step.json in the OFF's numbering.
    const LimbEdit step{771, 681, 771, 0.03, {0.08, 0.03, 0.0}};
    for (const char* file : {"cow.glb", "cow.gltf", "cow-embedded.gltf"})
        check_seamless_edit(file, "cow.off", step);
}
