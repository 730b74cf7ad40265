#include <doctest/doctest.h>

#include <cstdlib>
#include <cstring>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include "dualform/dualform.h"
#include "sdk/sdk_fixture.hpp"
#include "support/procedural_meshes.hpp"
#include "support/test_files.hpp"

using namespace dfm::test;

namespace {

// Counts the host allocator's traffic; fails every call from `fail_from` on.
struct CountingAllocator {
    std::size_t allocations = 0;
    std::size_t frees = 0;
    std::size_t live_bytes = 0;
    std::size_t fail_from = SIZE_MAX;

    static void* alloc(void* user, std::size_t size, std::size_t alignment) {
        auto* self = static_cast<CountingAllocator*>(user);
        if (self->allocations >= self->fail_from) return nullptr;
        ++self->allocations;
        self->live_bytes += size;
        return std::aligned_alloc(alignment, (size + alignment - 1) / alignment * alignment);
    }
    static void release(void* user, void* memory, std::size_t size) {
        auto* self = static_cast<CountingAllocator*>(user);
        ++self->frees;
        self->live_bytes -= size;
        std::free(memory);
    }
    dfm_allocator hooks() { return {&alloc, &release, this}; }
};

}  // namespace

TEST_CASE("context: version and result names and the last error message") {
    CHECK(dfm_version() == DFM_VERSION);
    CHECK(DFM_VERSION == DFM_VERSION_MAJOR * 10000 + DFM_VERSION_MINOR * 100 + DFM_VERSION_PATCH);
    CHECK(std::string(dfm_result_name(DFM_ERROR_PARSE)) == "DFM_ERROR_PARSE");
    CHECK(std::string(dfm_result_name(static_cast<dfm_result>(999))) == "DFM_ERROR_UNKNOWN");
    CHECK(dfm_context_create(nullptr, nullptr) == DFM_ERROR_INVALID_ARGUMENT);
    CHECK(dfm_last_error_code() == DFM_ERROR_INVALID_ARGUMENT);
    CHECK(std::string(dfm_last_error_message()) == "dfm_context_create: out is NULL");
}

TEST_CASE("context: the last error is per thread") {
    CHECK(dfm_context_create(nullptr, nullptr) == DFM_ERROR_INVALID_ARGUMENT);
    std::string seen_elsewhere = "unset";
    std::thread other([&] { seen_elsewhere = dfm_last_error_message(); });
    other.join();
    CHECK(seen_elsewhere.empty());
    CHECK(std::string(dfm_last_error_message()).find("dfm_context_create") == 0);
}

TEST_CASE("context: context descriptors are checked") {
    dfm_context* context = reinterpret_cast<dfm_context*>(0x1);
    dfm_context_desc desc = {};
    desc.allocator.alloc = &CountingAllocator::alloc;
    CHECK(dfm_context_create(&desc, &context) == DFM_ERROR_INVALID_ARGUMENT);
    CHECK(context == nullptr);
    CHECK(std::string(dfm_last_error_message()).find("alloc and free") != std::string::npos);
    desc = dfm_context_desc{};
    desc.worker_count = 100000;
    CHECK(dfm_context_create(&desc, &context) == DFM_ERROR_INVALID_ARGUMENT);
    dfm_context_destroy(nullptr);
    dfm_mesh_destroy(nullptr);
    dfm_roi_destroy(nullptr);
    dfm_session_destroy(nullptr);
}

TEST_CASE("context: every object goes through the host allocator and comes back") {
    CountingAllocator counter;
    dfm_context_desc desc = {};
    desc.allocator = counter.hooks();
    dfm_context* context = nullptr;
    REQUIRE(dfm_context_create(&desc, &context) == DFM_OK);
    {
        LimbEdit probe;  // for its shape only
        dfm_mesh* mesh = make_c_mesh(context, probe.shape);
        dfm_roi* roi = nullptr;
        REQUIRE(dfm_roi_all(mesh, &roi) == DFM_OK);
        dfm_roi* base = nullptr;
        REQUIRE(dfm_roi_boundary(roi, &base) == DFM_ERROR_NOT_FOUND);
        std::vector<std::uint32_t> region, tip;
        for (std::uint32_t v = 0; v < probe.shape.vertex_count(); ++v) {
            if (probe.shape.positions[v].y > 0.5) region.push_back(v);
            if (probe.shape.positions[v].y >= 1.8) tip.push_back(v);
        }
        dfm_roi* upper = nullptr;
        REQUIRE(dfm_roi_from_vertices(mesh, region.data(), region.size(), &upper) == DFM_OK);
        const dfm_handle_group group = {tip.data(), tip.size()};
        dfm_session_desc sd = {};
        sd.roi = upper;
        sd.groups = &group;
        sd.group_count = 1;
        dfm_session* session = nullptr;
        REQUIRE(dfm_session_create(mesh, &sd, &session) == DFM_OK);
        CHECK(counter.allocations >= 6);
        dfm_session_destroy(session);
        dfm_roi_destroy(upper);
        dfm_roi_destroy(roi);
        dfm_mesh_destroy(mesh);
    }
    dfm_context_destroy(context);
    CHECK(counter.frees == counter.allocations);
    CHECK(counter.live_bytes == 0);
}

TEST_CASE("context: a failing host allocator gives out-of-memory at every step and never a crash") {
    LimbEdit probe;
    // Fail the k-th allocation for every k until the whole sequence passes.
    std::size_t k = 0;
    for (;; ++k) {
        CountingAllocator counter;
        counter.fail_from = k;
        dfm_context_desc desc = {};
        desc.allocator = counter.hooks();
        dfm_context* context = nullptr;
        dfm_mesh* mesh = nullptr;
        dfm_roi* roi = nullptr;
        dfm_result r = dfm_context_create(&desc, &context);
        if (r == DFM_OK) {
            std::vector<float> xyz;
            for (const glm::dvec3& p : probe.shape.positions) {
                xyz.insert(xyz.end(), {float(p.x), float(p.y), float(p.z)});
            }
            dfm_mesh_desc md = {};
            md.positions = {xyz.data(), probe.shape.vertex_count(), 0, DFM_SCALAR_FLOAT32};
            md.indices = probe.shape.triangles.front().data();
            md.triangle_count = probe.shape.face_count();
            r = dfm_mesh_create(context, &md, &mesh);
        }
        if (r == DFM_OK) r = dfm_roi_all(mesh, &roi);
        if (r != DFM_OK) {
            CHECK(r == DFM_ERROR_OUT_OF_MEMORY);
            CHECK(std::string(dfm_last_error_message()).find("out of memory") != std::string::npos);
        }
        dfm_roi_destroy(roi);
        dfm_mesh_destroy(mesh);
        dfm_context_destroy(context);
        CHECK(counter.frees == counter.allocations);
        if (r == DFM_OK) break;
    }
    MESSAGE("host allocation points exercised: " << k);
    CHECK(k >= 3);
}

TEST_CASE("context: the log callback hears load warnings, suspect fills and capped solves") {
    struct Heard {
        std::vector<dfm_log_id> ids;
        std::vector<std::string> messages;
    } heard;
    dfm_context_desc desc = {};
    desc.log = [](void* user, dfm_log_level, dfm_log_id id, const char* message) {
        auto* h = static_cast<Heard*>(user);
        h->ids.push_back(id);
        h->messages.emplace_back(message);
    };
    desc.log_user = &heard;
    dfm_context* context = nullptr;
    REQUIRE(dfm_context_create(&desc, &context) == DFM_OK);

    // A tetrahedron whose fifth face repeats a vertex: dropped with a warning.
    const std::string path = (dfm::test::scratch_dir("sdk_log") / "tetra.off").string();
    std::ofstream(path) << "OFF\n4 5 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n"
                           "3 0 2 1\n3 0 1 3\n3 1 2 3\n3 2 0 3\n3 0 0 1\n";
    dfm_mesh* tetra = nullptr;
    REQUIRE_MESSAGE(dfm_mesh_load(context, path.c_str(), &tetra) == DFM_OK, last_error());
    REQUIRE(heard.ids.size() == 1);
    CHECK(heard.ids[0] == DFM_LOG_ID_LOAD_WARNING);
    CHECK(heard.messages[0].find("tetra.off") != std::string::npos);
    dfm_mesh_destroy(tetra);

    // Water-Filling from one pole of a sphere to the other leaks over most of it.
    dfm_mesh* sphere = make_c_mesh(context, dfm::test::make_icosphere(2));
    const dfm::mesh::Mesh shape = dfm::test::make_icosphere(2);
    std::uint32_t top = 0, bottom = 0;
    for (std::uint32_t v = 0; v < shape.vertex_count(); ++v) {
        if (shape.positions[v].z > shape.positions[top].z) top = v;
        if (shape.positions[v].z < shape.positions[bottom].z) bottom = v;
    }
    dfm_roi* fill = nullptr;
    dfm_water_fill_diagnosis diagnosis = {};
    REQUIRE(dfm_roi_water_fill(sphere, top, bottom, &fill, &diagnosis) == DFM_OK);
    CHECK(diagnosis.suspect);
    REQUIRE(heard.ids.size() == 2);
    CHECK(heard.ids[1] == DFM_LOG_ID_WATER_FILL_SUSPECT);
    dfm_roi_destroy(fill);
    dfm_mesh_destroy(sphere);

    // A solve capped at one iteration.
    LimbEdit probe;
    dfm_mesh* limb = make_c_mesh(context, probe.shape);
    std::vector<std::uint32_t> region, tip;
    for (std::uint32_t v = 0; v < probe.shape.vertex_count(); ++v) {
        if (probe.shape.positions[v].y > 0.5) region.push_back(v);
        if (probe.shape.positions[v].y >= 1.8) tip.push_back(v);
    }
    dfm_roi* roi = nullptr;
    REQUIRE(dfm_roi_from_vertices(limb, region.data(), region.size(), &roi) == DFM_OK);
    const dfm_handle_group group = {tip.data(), tip.size()};
    dfm_session_desc sd = {};
    sd.roi = roi;
    sd.groups = &group;
    sd.group_count = 1;
    sd.solver.max_iterations = 1;
    sd.solver.tolerance = 1e-14;
    dfm_session* session = nullptr;
    REQUIRE(dfm_session_create(limb, &sd, &session) == DFM_OK);
    double m[16];
    translation(0.4, 0.0, 0.0, m);
    REQUIRE(dfm_session_set_group_transform(session, 0, m) == DFM_OK);
    REQUIRE(dfm_session_solve(session, nullptr) == DFM_OK);
    REQUIRE(heard.ids.size() == 3);
    CHECK(heard.ids[2] == DFM_LOG_ID_SOLVE_NOT_CONVERGED);
    dfm_session_destroy(session);
    dfm_roi_destroy(roi);
    dfm_mesh_destroy(limb);
    dfm_context_destroy(context);
}
