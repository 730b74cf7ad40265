#include <doctest/doctest.h>

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <vector>

#include "dualform/dualform.h"
#include "sdk/sdk_fixture.hpp"

using namespace dfm::test;

namespace {

// A descriptor as a caller built against an older header fills it: only
// `size` bytes are its own, and what lies beyond is someone else's (here
// 0xFF, which as a callback pointer would crash if read).
template <class Desc>
std::vector<unsigned char> older_caller(const Desc& full, std::size_t size) {
    std::vector<unsigned char> bytes(sizeof(Desc) + 64, 0xFF);
    std::memcpy(bytes.data(), &full, size);
    const auto size32 = static_cast<std::uint32_t>(size);
    std::memcpy(bytes.data(), &size32, sizeof size32);
    return bytes;
}

}  // namespace

TEST_CASE("descriptors: a caller built against a smaller session descriptor still works") {
    LimbEdit limb;
    const dfm_handle_group group = {limb.tip.data(), limb.tip.size()};
    dfm_session_desc full = {};
    full.roi = limb.roi;
    full.groups = &group;
    full.group_count = 1;
    // As if the frame-ready callback fields did not exist yet.
    const std::vector<unsigned char> bytes =
        older_caller(full, offsetof(dfm_session_desc, on_frame));
    dfm_session* session = nullptr;
    REQUIRE_MESSAGE(
        dfm_session_create(limb.mesh, reinterpret_cast<const dfm_session_desc*>(bytes.data()),
                           &session) == DFM_OK,
        last_error());
    double m[16];
    translation(0.2, 0, 0, m);
    REQUIRE(dfm_session_set_group_transform(session, 0, m) == DFM_OK);
    std::uint64_t g = 0;
    REQUIRE(dfm_session_submit(session, &g) == DFM_OK);
    CHECK(dfm_session_wait(session, g, -1, nullptr) == DFM_OK);
    dfm_session_destroy(session);
}

TEST_CASE("descriptors: smaller context and mesh descriptors take defaults for what they lack") {
    dfm_context_desc full = {};
    full.worker_count = 2;
    const std::vector<unsigned char> bytes =
        older_caller(full, offsetof(dfm_context_desc, worker_count));
    dfm_context* context = nullptr;
    REQUIRE_MESSAGE(dfm_context_create(reinterpret_cast<const dfm_context_desc*>(bytes.data()),
                                       &context) == DFM_OK,
                    last_error());
    const std::vector<float> xyz = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1};
    const std::uint32_t tris[] = {0, 1, 2, 0, 3, 1, 0, 2, 3, 1, 3, 2};
    dfm_mesh_desc mesh_full = {};
    mesh_full.positions = {xyz.data(), 4, 0, DFM_SCALAR_FLOAT32};
    mesh_full.indices = tris;
    mesh_full.triangle_count = 4;
    // Without index_stride: packed.
    const std::vector<unsigned char> mesh_bytes =
        older_caller(mesh_full, offsetof(dfm_mesh_desc, index_stride));
    dfm_mesh* mesh = nullptr;
    REQUIRE_MESSAGE(
        dfm_mesh_create(context, reinterpret_cast<const dfm_mesh_desc*>(mesh_bytes.data()),
                        &mesh) == DFM_OK,
        last_error());
    dfm_mesh_info info = {};
    REQUIRE(dfm_mesh_get_info(mesh, &info) == DFM_OK);
    CHECK(info.triangle_count == 4);
    dfm_mesh_destroy(mesh);
    dfm_context_destroy(context);
}

TEST_CASE("descriptors: a newer caller's larger descriptor is accepted only if its extra is zero") {
    std::vector<unsigned char> bytes(sizeof(dfm_context_desc) + 16, 0);
    const auto size = static_cast<std::uint32_t>(bytes.size());
    std::memcpy(bytes.data(), &size, sizeof size);
    dfm_context* context = nullptr;
    const auto* desc = reinterpret_cast<const dfm_context_desc*>(bytes.data());
    REQUIRE(dfm_context_create(desc, &context) == DFM_OK);
    dfm_context_destroy(context);
    bytes[sizeof(dfm_context_desc) + 3] = 1;
    CHECK(dfm_context_create(desc, &context) == DFM_ERROR_UNSUPPORTED);
    CHECK(message_has("of a newer field is set"));
    CHECK(context == nullptr);
    const std::uint32_t too_small = 2;
    std::memcpy(bytes.data(), &too_small, sizeof too_small);
    CHECK(dfm_context_create(desc, &context) == DFM_ERROR_INVALID_ARGUMENT);
}

TEST_CASE("descriptors: reserved solver words must be zero") {
    LimbEdit limb;
    dfm_solver_settings settings = {};
    settings.reserved[3] = 7;
    CHECK(dfm_session_set_solver(limb.session, &settings) == DFM_ERROR_UNSUPPORTED);
    CHECK(message_has("reserved[3]"));
}

TEST_CASE("descriptors: the library checks the header version a caller was built with") {
    CHECK(dfm_version_compatible(DFM_VERSION));
    CHECK(DFM_VERSION_MATCHES());
    CHECK_FALSE(dfm_version_compatible(DFM_VERSION + 10000));
    CHECK_FALSE(dfm_version_compatible(DFM_VERSION + 100));  // before 1.0 a minor breaks
    CHECK(dfm_version_compatible(DFM_VERSION - DFM_VERSION_PATCH + 7));
    dfm_context_desc desc = {};
    desc.struct_size = sizeof desc;
    desc.header_version = DFM_VERSION + 100;
    dfm_context* context = nullptr;
    CHECK(dfm_context_create(&desc, &context) == DFM_ERROR_UNSUPPORTED);
    CHECK(message_has("built with the header of version"));
    desc.header_version = DFM_VERSION;
    REQUIRE(dfm_context_create(&desc, &context) == DFM_OK);
    dfm_context_destroy(context);
}
