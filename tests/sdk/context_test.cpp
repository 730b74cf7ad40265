#include <doctest/doctest.h>

#include <cstdlib>
#include <cstring>
#include <string>
#include <thread>
#include <vector>

#include "dualform/dualform.h"
#include "sdk/sdk_fixture.hpp"
#include "support/procedural_meshes.hpp"

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
