#include <doctest/doctest.h>

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "descriptor_layouts.hpp"
#include "dualform/dualform.h"
#include "sdk/sdk_fixture.hpp"
#include "support/layout_checks.hpp"
#include "support/test_files.hpp"

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

TEST_CASE("descriptors: struct_size 0 reads every field of the 0.2 layout") {
    dfm_context* context = nullptr;
    REQUIRE(dfm_context_create(nullptr, &context) == DFM_OK);
    // Two triangles that share an edge through copies of its two vertices:
    // the weld (a 0.2 field) joins them, 6 host vertices into 4.
    const std::vector<float> xyz = {0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
    const std::uint32_t tris[] = {0, 1, 2, 3, 4, 5};
    dfm_mesh_desc md = {};
    md.positions = {xyz.data(), 6, 0, DFM_SCALAR_FLOAT32};
    md.indices = tris;
    md.triangle_count = 2;
    md.weld = DFM_WELD_EXACT;
    dfm_mesh* mesh = nullptr;
    REQUIRE_MESSAGE(dfm_mesh_create(context, &md, &mesh) == DFM_OK, last_error());
    dfm_mesh_info info = {};
    REQUIRE(dfm_mesh_get_info(mesh, &info) == DFM_OK);
    CHECK(info.vertex_count == 6);
    CHECK(info.surface_vertex_count == 4);

    // A morph target (a 0.2 field) is written only into a glTF asset.
    dfm_save_options options = {};
    options.morph_target_name = "edit";
    const std::string path = (scratch_dir("sdk_descriptors") / "quad.off").string();
    CHECK(dfm_mesh_save_with_options(mesh, path.c_str(), &options) == DFM_ERROR_UNSUPPORTED);
    CHECK(message_has("morph target"));
    dfm_mesh_destroy(mesh);
    dfm_context_destroy(context);
}

namespace {

// The 0.2 layouts, as the 0.2.0 header declares them: a later version adds
// fields to the structs, and these copies stay as they are.
namespace v0_2 {

struct context_desc {
    std::uint32_t struct_size;
    std::uint32_t header_version;
    dfm_allocator allocator;
    dfm_log_fn log;
    void* log_user;
    std::uint32_t worker_count;
    std::uint32_t pick_thread_count;
    const char* models_directory;
    const char* reference_folder;
    dfm_work_mode work_mode;
    dfm_job_system job_system;
};

struct mesh_desc {
    std::uint32_t struct_size;
    dfm_vec3_input positions;
    const std::uint32_t* indices;
    std::size_t triangle_count;
    std::size_t index_stride;
    dfm_weld_mode weld;
    double weld_tolerance;
    dfm_skin_input skin;
};

struct session_desc {
    std::uint32_t struct_size;
    const dfm_roi* roi;
    const dfm_handle_group* groups;
    std::size_t group_count;
    dfm_solver_settings solver;
    dfm_frame_ready_fn on_frame;
    void* on_frame_user;
};

struct vertex_output {
    std::uint32_t struct_size;
    void* data;
    std::size_t count;
    std::size_t stride;
    std::size_t position_offset;
    std::size_t normal_offset;
    bool write_positions;
    bool write_normals;
    bool changed_only;
};

struct solve_details {
    std::uint32_t struct_size;
    double setup_rows_ms;
    double setup_assembly_ms;
    double setup_ordering_ms;
    double setup_symbolic_ms;
    double setup_numeric_ms;
    double linear_solve_ms;
    double right_hand_side_ms;
    double normals_ms;
    double anderson_ms;
    bool predicted;
};

struct save_options {
    std::uint32_t struct_size;
    dfm_ply_encoding ply_encoding;
    bool ply_float;
    bool obj_normals;
    const char* morph_target_name;
};

}  // namespace v0_2

}  // namespace

TEST_CASE("descriptors: the library's struct_size 0 is each struct's 0.2 layout") {
    using dfm::sdk::FirstLayout;
    CHECK(FirstLayout<dfm_context_desc>::size == DFM_END_OF(v0_2::context_desc, job_system));
    CHECK_SAME_PLACE(v0_2::context_desc, dfm_context_desc, header_version);
    CHECK_SAME_PLACE(v0_2::context_desc, dfm_context_desc, allocator);
    CHECK_SAME_PLACE(v0_2::context_desc, dfm_context_desc, log);
    CHECK_SAME_PLACE(v0_2::context_desc, dfm_context_desc, log_user);
    CHECK_SAME_PLACE(v0_2::context_desc, dfm_context_desc, worker_count);
    CHECK_SAME_PLACE(v0_2::context_desc, dfm_context_desc, pick_thread_count);
    CHECK_SAME_PLACE(v0_2::context_desc, dfm_context_desc, models_directory);
    CHECK_SAME_PLACE(v0_2::context_desc, dfm_context_desc, reference_folder);
    CHECK_SAME_PLACE(v0_2::context_desc, dfm_context_desc, work_mode);
    CHECK_SAME_PLACE(v0_2::context_desc, dfm_context_desc, job_system);

    CHECK(FirstLayout<dfm_mesh_desc>::size == DFM_END_OF(v0_2::mesh_desc, skin));
    CHECK_SAME_PLACE(v0_2::mesh_desc, dfm_mesh_desc, positions);
    CHECK_SAME_PLACE(v0_2::mesh_desc, dfm_mesh_desc, indices);
    CHECK_SAME_PLACE(v0_2::mesh_desc, dfm_mesh_desc, triangle_count);
    CHECK_SAME_PLACE(v0_2::mesh_desc, dfm_mesh_desc, index_stride);
    CHECK_SAME_PLACE(v0_2::mesh_desc, dfm_mesh_desc, weld);
    CHECK_SAME_PLACE(v0_2::mesh_desc, dfm_mesh_desc, weld_tolerance);
    CHECK_SAME_PLACE(v0_2::mesh_desc, dfm_mesh_desc, skin);

    CHECK(FirstLayout<dfm_session_desc>::size == DFM_END_OF(v0_2::session_desc, on_frame_user));
    CHECK_SAME_PLACE(v0_2::session_desc, dfm_session_desc, roi);
    CHECK_SAME_PLACE(v0_2::session_desc, dfm_session_desc, groups);
    CHECK_SAME_PLACE(v0_2::session_desc, dfm_session_desc, group_count);
    CHECK_SAME_PLACE(v0_2::session_desc, dfm_session_desc, solver);
    CHECK_SAME_PLACE(v0_2::session_desc, dfm_session_desc, on_frame);
    CHECK_SAME_PLACE(v0_2::session_desc, dfm_session_desc, on_frame_user);

    CHECK(FirstLayout<dfm_vertex_output>::size == DFM_END_OF(v0_2::vertex_output, changed_only));
    CHECK_SAME_PLACE(v0_2::vertex_output, dfm_vertex_output, data);
    CHECK_SAME_PLACE(v0_2::vertex_output, dfm_vertex_output, count);
    CHECK_SAME_PLACE(v0_2::vertex_output, dfm_vertex_output, stride);
    CHECK_SAME_PLACE(v0_2::vertex_output, dfm_vertex_output, position_offset);
    CHECK_SAME_PLACE(v0_2::vertex_output, dfm_vertex_output, normal_offset);
    CHECK_SAME_PLACE(v0_2::vertex_output, dfm_vertex_output, write_positions);
    CHECK_SAME_PLACE(v0_2::vertex_output, dfm_vertex_output, write_normals);
    CHECK_SAME_PLACE(v0_2::vertex_output, dfm_vertex_output, changed_only);

    CHECK(FirstLayout<dfm_solve_details>::size == DFM_END_OF(v0_2::solve_details, predicted));
    CHECK_SAME_PLACE(v0_2::solve_details, dfm_solve_details, setup_rows_ms);
    CHECK_SAME_PLACE(v0_2::solve_details, dfm_solve_details, setup_assembly_ms);
    CHECK_SAME_PLACE(v0_2::solve_details, dfm_solve_details, setup_ordering_ms);
    CHECK_SAME_PLACE(v0_2::solve_details, dfm_solve_details, setup_symbolic_ms);
    CHECK_SAME_PLACE(v0_2::solve_details, dfm_solve_details, setup_numeric_ms);
    CHECK_SAME_PLACE(v0_2::solve_details, dfm_solve_details, linear_solve_ms);
    CHECK_SAME_PLACE(v0_2::solve_details, dfm_solve_details, right_hand_side_ms);
    CHECK_SAME_PLACE(v0_2::solve_details, dfm_solve_details, normals_ms);
    CHECK_SAME_PLACE(v0_2::solve_details, dfm_solve_details, anderson_ms);
    CHECK_SAME_PLACE(v0_2::solve_details, dfm_solve_details, predicted);

    CHECK(FirstLayout<dfm_save_options>::size == DFM_END_OF(v0_2::save_options, morph_target_name));
    CHECK_SAME_PLACE(v0_2::save_options, dfm_save_options, ply_encoding);
    CHECK_SAME_PLACE(v0_2::save_options, dfm_save_options, ply_float);
    CHECK_SAME_PLACE(v0_2::save_options, dfm_save_options, obj_normals);
    CHECK_SAME_PLACE(v0_2::save_options, dfm_save_options, morph_target_name);
}
