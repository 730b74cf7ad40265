#include <doctest/doctest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

#include "dualform/dualform.h"
#include "sdk/sdk_fixture.hpp"
#include "support/procedural_meshes.hpp"

using namespace dfm::test;

namespace {

// A game's vertex: position, texture coordinates, normal, colour.
struct Vertex {
    float position[3];
    float uv[2];
    float normal[3];
    std::uint32_t colour;
};

constexpr std::uint32_t sentinel = 0xDEADBEEF;

dfm_vertex_output interleaved(std::vector<Vertex>& buffer) {
    dfm_vertex_output out = {};
    out.struct_size = sizeof out;
    out.data = buffer.data();
    out.count = buffer.size();
    out.stride = sizeof(Vertex);
    out.position_offset = offsetof(Vertex, position);
    out.normal_offset = offsetof(Vertex, normal);
    out.write_positions = true;
    out.write_normals = true;
    return out;
}

}  // namespace

TEST_CASE("host buffers: positions and normals land in an interleaved vertex buffer") {
    LimbEdit limb;
    const std::size_t n = limb.shape.vertex_count();
    double m[16];
    translation(0.3, 0.1, 0, m);
    REQUIRE(dfm_session_set_group_transform(limb.session, 0, m) == DFM_OK);
    std::uint64_t g = 0;
    REQUIRE(dfm_session_submit(limb.session, &g) == DFM_OK);
    REQUIRE(dfm_session_wait(limb.session, g, -1, nullptr) == DFM_OK);

    std::vector<float> positions(3 * n), normals(3 * n);
    const dfm_vec3_output p_out = {positions.data(), n, 0, DFM_SCALAR_FLOAT32};
    const dfm_vec3_output n_out = {normals.data(), n, 0, DFM_SCALAR_FLOAT32};
    REQUIRE(dfm_session_read_positions(limb.session, &p_out, nullptr) == DFM_OK);
    REQUIRE(dfm_session_read_normals(limb.session, &n_out, nullptr) == DFM_OK);

    std::vector<Vertex> buffer(n);
    for (Vertex& v : buffer) {
        v.uv[0] = 0.25f;
        v.uv[1] = 0.75f;
        v.colour = sentinel;
    }
    const dfm_vertex_output out = interleaved(buffer);
    dfm_frame_info info = {};
    REQUIRE_MESSAGE(dfm_session_read_vertices(limb.session, &out, &info) == DFM_OK, last_error());
    CHECK(info.generation == g);
    std::size_t wrong = 0;
    for (std::size_t v = 0; v < n; ++v) {
        if (std::memcmp(buffer[v].position, &positions[3 * v], 12) != 0) ++wrong;
        if (std::memcmp(buffer[v].normal, &normals[3 * v], 12) != 0) ++wrong;
        if (buffer[v].colour != sentinel || buffer[v].uv[0] != 0.25f || buffer[v].uv[1] != 0.75f) {
            ++wrong;
        }
    }
    CHECK(wrong == 0);

    // Only the changing part: everything else keeps what the host had.
    std::vector<Vertex> partial(n);
    std::memset(partial.data(), 0xFF, partial.size() * sizeof(Vertex));
    dfm_vertex_output changed = interleaved(partial);
    changed.changed_only = true;
    REQUIRE(dfm_session_read_vertices(limb.session, &changed, nullptr) == DFM_OK);
    std::size_t written = 0, untouched = 0;
    for (std::size_t v = 0; v < n; ++v) {
        const bool in_roi = limb.shape.positions[v].y > 0.5;
        if (in_roi) {
            written += std::memcmp(partial[v].position, &positions[3 * v], 12) == 0;
        } else {
            std::uint32_t bits = 0;
            std::memcpy(&bits, &partial[v].position[0], 4);
            untouched += bits == 0xFFFFFFFFu;
        }
    }
    std::size_t roi = 0;
    REQUIRE(dfm_roi_count(limb.roi, &roi) == DFM_OK);
    CHECK(written == roi);
    CHECK(untouched == n - roi);

    dfm_vertex_output bad = interleaved(buffer);
    bad.stride = 20;
    CHECK(dfm_session_read_vertices(limb.session, &bad, nullptr) == DFM_ERROR_INVALID_ARGUMENT);
    CHECK(message_has("does not hold 12 bytes"));
    bad = interleaved(buffer);
    bad.count = n - 1;
    CHECK(dfm_session_read_vertices(limb.session, &bad, nullptr) == DFM_ERROR_INVALID_ARGUMENT);
    bad = interleaved(buffer);
    bad.write_positions = bad.write_normals = false;
    CHECK(dfm_session_read_vertices(limb.session, &bad, nullptr) == DFM_ERROR_INVALID_ARGUMENT);
}

TEST_CASE("host buffers: 16-bit indices for small meshes, refused past 65,536 vertices") {
    LimbEdit limb;
    const std::size_t t = limb.shape.face_count();
    std::vector<std::uint32_t> wide(3 * t);
    std::vector<std::uint16_t> narrow(3 * t);
    REQUIRE(dfm_mesh_read_indices(limb.mesh, wide.data(), wide.size()) == DFM_OK);
    REQUIRE(dfm_mesh_read_indices16(limb.mesh, narrow.data(), narrow.size()) == DFM_OK);
    CHECK(std::vector<std::uint32_t>(narrow.begin(), narrow.end()) == wide);
    CHECK(dfm_mesh_read_indices16(limb.mesh, narrow.data(), narrow.size() - 1) ==
          DFM_ERROR_INVALID_ARGUMENT);

    const dfm::mesh::Mesh big = make_limb(256, 260, 0.2, 2.0);
    REQUIRE(big.vertex_count() > 65536);
    dfm_mesh* large = make_c_mesh(limb.context, big);
    std::vector<std::uint16_t> too_small(3 * big.face_count());
    CHECK(dfm_mesh_read_indices16(large, too_small.data(), too_small.size()) ==
          DFM_ERROR_OUT_OF_RANGE);
    CHECK(message_has("more than 16-bit indices reach"));
    dfm_mesh_destroy(large);
}

TEST_CASE("host buffers: the host updates the rest pose, earlier sessions are told BUSY") {
    LimbEdit limb;
    const std::size_t n = limb.shape.vertex_count();
    std::vector<double> rest(3 * n), moved(3 * n), now(3 * n);
    const dfm_vec3_output out_now = {now.data(), n, 0, DFM_SCALAR_FLOAT64};
    REQUIRE(dfm_mesh_read_positions(limb.mesh, &out_now) == DFM_OK);
    rest = now;
    for (std::size_t i = 0; i < moved.size(); ++i) moved[i] = rest[i] + (i % 3 == 2 ? 0.5 : 0.0);
    const dfm_vec3_input in = {moved.data(), n, 0, DFM_SCALAR_FLOAT64};
    REQUIRE_MESSAGE(dfm_mesh_set_positions(limb.mesh, &in) == DFM_OK, last_error());
    REQUIRE(dfm_mesh_read_positions(limb.mesh, &out_now) == DFM_OK);
    CHECK(now == moved);
    dfm_mesh_info info = {};
    REQUIRE(dfm_mesh_get_info(limb.mesh, &info) == DFM_OK);
    CHECK(info.bake_count == 1);
    REQUIRE(dfm_session_wait(limb.session, 0, -1, nullptr) == DFM_OK);
    CHECK(dfm_session_bake(limb.session) == DFM_ERROR_BUSY);
    CHECK(message_has("rest pose changed"));
    // A new session edits the updated pose.
    const dfm_handle_group group = {limb.tip.data(), limb.tip.size()};
    dfm_session_desc desc = {};
    desc.roi = limb.roi;
    desc.groups = &group;
    desc.group_count = 1;
    dfm_session* fresh = nullptr;
    REQUIRE(dfm_session_create(limb.mesh, &desc, &fresh) == DFM_OK);
    std::vector<double> frame(3 * n);
    const dfm_vec3_output out_frame = {frame.data(), n, 0, DFM_SCALAR_FLOAT64};
    REQUIRE(dfm_session_read_positions(fresh, &out_frame, nullptr) == DFM_OK);
    CHECK(frame == moved);
    dfm_session_destroy(fresh);
    REQUIRE(dfm_mesh_undo_bake(limb.mesh) == DFM_OK);
    REQUIRE(dfm_mesh_read_positions(limb.mesh, &out_now) == DFM_OK);
    CHECK(now == rest);

    moved[3 * 7 + 1] = std::numeric_limits<double>::quiet_NaN();
    CHECK(dfm_mesh_set_positions(limb.mesh, &in) == DFM_ERROR_NUMERICAL);
    CHECK(message_has("vertex 7 is not finite"));
    const dfm_vec3_input short_in = {moved.data(), n - 1, 0, DFM_SCALAR_FLOAT64};
    CHECK(dfm_mesh_set_positions(limb.mesh, &short_in) == DFM_ERROR_INVALID_ARGUMENT);
    REQUIRE(dfm_mesh_read_positions(limb.mesh, &out_now) == DFM_OK);
    CHECK(now == rest);
}

namespace {

// How many of this process's threads carry `name`.
int threads_named(const std::string& name) {
    int count = 0;
    for (const auto& task : std::filesystem::directory_iterator("/proc/self/task")) {
        std::ifstream comm(task.path() / "comm");
        std::string line;
        if (std::getline(comm, line) && line == name) ++count;
    }
    return count;
}

}  // namespace

TEST_CASE("threads: a context's worker_count named workers serve all its sessions") {
    const int before = threads_named("dfm-worker");
    dfm_context_desc desc = {};
    desc.struct_size = sizeof desc;
    desc.worker_count = 3;
    desc.pick_thread_count = 1;
    dfm_context* context = nullptr;
    REQUIRE(dfm_context_create(&desc, &context) == DFM_OK);
    CHECK(threads_named("dfm-worker") == before + 3);
    const dfm::mesh::Mesh shape = make_limb(16, 20, 0.2, 2.0);
    dfm_mesh* mesh = make_c_mesh(context, shape);
    std::vector<std::uint32_t> region, tip;
    for (std::uint32_t v = 0; v < shape.vertex_count(); ++v) {
        if (shape.positions[v].y > 0.5) region.push_back(v);
        if (shape.positions[v].y >= 1.8) tip.push_back(v);
    }
    dfm_roi* roi = nullptr;
    REQUIRE(dfm_roi_from_vertices(mesh, region.data(), region.size(), &roi) == DFM_OK);
    const dfm_handle_group group = {tip.data(), tip.size()};
    dfm_session_desc sd = {};
    sd.roi = roi;
    sd.groups = &group;
    sd.group_count = 1;
    std::vector<dfm_session*> sessions(5, nullptr);
    for (dfm_session*& session : sessions) {
        REQUIRE(dfm_session_create(mesh, &sd, &session) == DFM_OK);
    }
    for (dfm_session* session : sessions) {
        REQUIRE(dfm_session_wait(session, 0, -1, nullptr) == DFM_OK);
    }
    CHECK(threads_named("dfm-worker") == before + 3);
    // Picking with a one-thread Embree device works as with the default.
    const double origin[3] = {0, 10, 0}, down[3] = {0, -1, 0};
    dfm_hit hit = {};
    REQUIRE(dfm_mesh_pick_ray(mesh, origin, down, &hit) == DFM_OK);
    CHECK(hit.hit);
    for (dfm_session* session : sessions) dfm_session_destroy(session);
    // The mesh outlives the context's handle, and the workers with it.
    dfm_context_destroy(context);
    CHECK(threads_named("dfm-worker") == before + 3);
    dfm_roi_destroy(roi);
    dfm_mesh_destroy(mesh);
    CHECK(threads_named("dfm-worker") == before);
    desc.pick_thread_count = 5000;
    dfm_context* refused = nullptr;
    CHECK(dfm_context_create(&desc, &refused) == DFM_ERROR_INVALID_ARGUMENT);
}
