#include <doctest/doctest.h>

#include <climits>
#include <cstdint>
#include <cstdlib>
#include <map>
#include <mutex>
#include <vector>

#include "dualform/dualform.h"
#include "sdk/sdk_fixture.hpp"
#include "support/procedural_meshes.hpp"

using namespace dfm::test;

namespace {

// A pool as engines use: a freed block goes on a list for its size and the
// next allocation of that size gets it straight back. With handles that
// were addresses, the next object's handle equalled the destroyed one's.
struct PoolAllocator {
    std::mutex mutex;
    std::map<std::size_t, std::vector<void*>> free_blocks;
    std::vector<void*> owned;
    std::size_t reused = 0;

    static void* alloc(void* user, std::size_t size, std::size_t alignment) {
        auto* self = static_cast<PoolAllocator*>(user);
        std::lock_guard<std::mutex> lock(self->mutex);
        std::vector<void*>& list = self->free_blocks[size];
        if (!list.empty()) {
            void* block = list.back();
            list.pop_back();
            ++self->reused;
            return block;
        }
        static_cast<void>(alignment);  // every block is 64-aligned
        void* block = std::aligned_alloc(64, (size + 63) / 64 * 64);
        self->owned.push_back(block);
        return block;
    }
    static void release(void* user, void* memory, std::size_t size) {
        auto* self = static_cast<PoolAllocator*>(user);
        std::lock_guard<std::mutex> lock(self->mutex);
        self->free_blocks[size].push_back(memory);
    }
    ~PoolAllocator() {
        for (void* block : owned) std::free(block);
    }
    dfm_context_desc context_desc() {
        dfm_context_desc desc = {};
        desc.struct_size = sizeof desc;
        desc.allocator = {&alloc, &release, this};
        return desc;
    }
};

dfm_session* start_session(dfm_mesh* mesh, dfm_roi* roi, const std::vector<std::uint32_t>& tip) {
    const dfm_handle_group group = {tip.data(), tip.size()};
    dfm_session_desc desc = {};
    desc.roi = roi;
    desc.groups = &group;
    desc.group_count = 1;
    dfm_session* session = nullptr;
    REQUIRE_MESSAGE(dfm_session_create(mesh, &desc, &session) == DFM_OK, last_error());
    return session;
}

}  // namespace

TEST_CASE("handles: a destroyed handle stays refused when a pool hands its memory to the next") {
    PoolAllocator pool;
    const dfm::mesh::Mesh shape = make_limb(12, 16, 0.2, 2.0);
    const dfm_context_desc desc = pool.context_desc();

    SUBCASE("context") {
        dfm_context* a = nullptr;
        REQUIRE(dfm_context_create(&desc, &a) == DFM_OK);
        dfm_context_destroy(a);
        const std::size_t reused = pool.reused;
        dfm_context* b = nullptr;
        REQUIRE(dfm_context_create(&desc, &b) == DFM_OK);
        CHECK(pool.reused > reused);
        CHECK(b != a);
        dfm_mesh* m = nullptr;
        const std::vector<float> xyz = {0, 0, 0, 1, 0, 0, 0, 1, 0};
        const std::uint32_t tri[] = {0, 1, 2};
        dfm_mesh_desc md = {};
        md.positions = {xyz.data(), 3, 0, DFM_SCALAR_FLOAT32};
        md.indices = tri;
        md.triangle_count = 1;
        CHECK(dfm_mesh_create(a, &md, &m) == DFM_ERROR_INVALID_HANDLE);
        CHECK(m == nullptr);
        dfm_context_destroy(a);
        REQUIRE(dfm_mesh_create(b, &md, &m) == DFM_OK);
        dfm_mesh_destroy(m);
        dfm_context_destroy(b);
    }
    SUBCASE("mesh") {
        dfm_context* context = nullptr;
        REQUIRE(dfm_context_create(&desc, &context) == DFM_OK);
        dfm_mesh* a = make_c_mesh(context, shape);
        dfm_mesh_destroy(a);
        const std::size_t reused = pool.reused;
        dfm_mesh* b = make_c_mesh(context, shape);
        CHECK(pool.reused > reused);
        CHECK(b != a);
        dfm_mesh_info info = {};
        CHECK(dfm_mesh_get_info(a, &info) == DFM_ERROR_INVALID_HANDLE);
        CHECK(message_has("mesh is not a live handle"));
        dfm_mesh_destroy(a);
        REQUIRE(dfm_mesh_get_info(b, &info) == DFM_OK);
        CHECK(info.vertex_count == shape.vertex_count());
        dfm_mesh_destroy(b);
        dfm_context_destroy(context);
    }
    SUBCASE("roi") {
        dfm_context* context = nullptr;
        REQUIRE(dfm_context_create(&desc, &context) == DFM_OK);
        dfm_mesh* mesh = make_c_mesh(context, shape);
        dfm_roi* a = nullptr;
        REQUIRE(dfm_roi_ball(mesh, 0, 0.1, &a) == DFM_OK);
        dfm_roi_destroy(a);
        const std::size_t reused = pool.reused;
        dfm_roi* b = nullptr;
        REQUIRE(dfm_roi_ball(mesh, 5, 0.3, &b) == DFM_OK);
        CHECK(pool.reused > reused);
        CHECK(b != a);
        std::size_t count_a = 0, count_b = 0;
        CHECK(dfm_roi_count(a, &count_a) == DFM_ERROR_INVALID_HANDLE);
        dfm_roi_destroy(a);  // a no-op: b lives on
        REQUIRE(dfm_roi_count(b, &count_b) == DFM_OK);
        CHECK(count_b > 1);
        dfm_roi_destroy(b);
        dfm_mesh_destroy(mesh);
        dfm_context_destroy(context);
    }
    SUBCASE("session") {
        dfm_context* context = nullptr;
        REQUIRE(dfm_context_create(&desc, &context) == DFM_OK);
        dfm_mesh* mesh = make_c_mesh(context, shape);
        std::vector<std::uint32_t> region, tip;
        for (std::uint32_t v = 0; v < shape.vertex_count(); ++v) {
            if (shape.positions[v].y > 0.5) region.push_back(v);
            if (shape.positions[v].y >= 1.8) tip.push_back(v);
        }
        dfm_roi* roi = nullptr;
        REQUIRE(dfm_roi_from_vertices(mesh, region.data(), region.size(), &roi) == DFM_OK);
        dfm_session* a = start_session(mesh, roi, tip);
        dfm_session_destroy(a);
        const std::size_t reused = pool.reused;
        dfm_session* b = start_session(mesh, roi, tip);
        CHECK(pool.reused > reused);
        CHECK(b != a);
        std::uint64_t g = 0;
        CHECK(dfm_session_submit(a, &g) == DFM_ERROR_INVALID_HANDLE);
        CHECK(g == 0);
        dfm_session_destroy(a);
        double m[16];
        translation(0.2, 0, 0, m);
        REQUIRE(dfm_session_set_group_transform(b, 0, m) == DFM_OK);
        REQUIRE(dfm_session_submit(b, &g) == DFM_OK);
        CHECK(g == 1);
        dfm_frame_info info = {};
        REQUIRE(dfm_session_wait(b, g, -1, &info) == DFM_OK);
        CHECK(info.generation == 1);
        dfm_session_destroy(b);
        dfm_roi_destroy(roi);
        dfm_mesh_destroy(mesh);
        dfm_context_destroy(context);
    }
}

TEST_CASE("handles: a handle of another kind or a made-up value is refused without a read") {
    LimbEdit limb;
    std::size_t count = 0;
    CHECK(dfm_roi_count(reinterpret_cast<const dfm_roi*>(limb.mesh), &count) ==
          DFM_ERROR_INVALID_HANDLE);
    CHECK(dfm_session_cancel(reinterpret_cast<dfm_session*>(limb.roi)) == DFM_ERROR_INVALID_HANDLE);
    int on_stack = 0;
    CHECK(dfm_roi_count(reinterpret_cast<const dfm_roi*>(&on_stack), &count) ==
          DFM_ERROR_INVALID_HANDLE);
    CHECK(dfm_roi_count(reinterpret_cast<const dfm_roi*>(std::uintptr_t{1}), &count) ==
          DFM_ERROR_INVALID_HANDLE);
    CHECK(dfm_roi_count(reinterpret_cast<const dfm_roi*>(~std::uintptr_t{0}), &count) ==
          DFM_ERROR_INVALID_HANDLE);
    dfm_roi_destroy(reinterpret_cast<dfm_roi*>(limb.mesh));  // not a ROI: nothing happens
    dfm_mesh_info info = {};
    CHECK(dfm_mesh_get_info(limb.mesh, &info) == DFM_OK);
}

TEST_CASE("handles: growing by INT_MIN rings is refused with a message, not undefined") {
    LimbEdit limb;
    dfm_roi* out = nullptr;
    CHECK(dfm_roi_grow(limb.roi, INT_MIN, &out) == DFM_ERROR_INVALID_ARGUMENT);
    CHECK(message_has("shrinking by 2147483648 rings leaves nothing"));
    CHECK(out == nullptr);
}
