// Every allocation of the main C API calls fails in turn: each failure must come back
// as DFM_ERROR_OUT_OF_MEMORY, leak nothing, and leave the objects usable.

#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include <doctest/doctest.h>

#include "reliability/allocation_sweep.hpp"
#include "reliability/failing_allocator.hpp"
#include "sdk/sdk_fixture.hpp"
#include "support/procedural_meshes.hpp"
#include "support/test_files.hpp"

namespace dfm::test {

namespace {

// A small limb, so that each sweep's thousands of steps stay quick: the
// edited region above y = 0.5, the handle at the tip.
struct SweepLimb {
    mesh::Mesh shape = make_limb(8, 6, 0.2, 2.0);
    std::vector<std::uint32_t> region;
    std::vector<std::uint32_t> tip;
    std::uint32_t tip_centre = 0;  // Water-Filling starts here...
    std::uint32_t middle = 0;      // ...and is cut by the plane through here

    SweepLimb() {
        for (std::uint32_t v = 0; v < shape.vertex_count(); ++v) {
            const glm::dvec3& p = shape.positions[v];
            if (p.y > 0.5) region.push_back(v);
            if (p.y >= 1.8) tip.push_back(v);
            if (p.y > shape.positions[tip_centre].y) tip_centre = v;
            if (std::abs(p.y - 1.0) < std::abs(shape.positions[middle].y - 1.0)) middle = v;
        }
    }
};

// One sweep step's objects, destroyed whatever the step's checks found.
struct Objects {
    dfm_context* context = nullptr;
    dfm_mesh* mesh = nullptr;
    dfm_roi* roi = nullptr;
    dfm_session* session = nullptr;

    Objects() {
        dfm_context_desc desc = {};
        desc.allocator = failable_host_allocator();
        REQUIRE(dfm_context_create(&desc, &context) == DFM_OK);
    }
    ~Objects() {
        dfm_session_destroy(session);
        dfm_roi_destroy(roi);
        dfm_mesh_destroy(mesh);
        dfm_context_destroy(context);
    }
    Objects(const Objects&) = delete;
    Objects& operator=(const Objects&) = delete;

    void make_session(const SweepLimb& limb) {
        mesh = make_c_mesh(context, limb.shape);
        REQUIRE(dfm_roi_from_vertices(mesh, limb.region.data(), limb.region.size(), &roi) ==
                DFM_OK);
        const dfm_session_desc desc = session_desc(limb);
        REQUIRE(dfm_session_create(mesh, &desc, &session) == DFM_OK);
    }

    // Points at `group`, which lives as long as these objects.
    dfm_session_desc session_desc(const SweepLimb& limb) {
        group = {limb.tip.data(), limb.tip.size()};
        dfm_session_desc desc = {};
        desc.roi = roi;
        desc.groups = &group;
        desc.group_count = 1;
        return desc;
    }

    dfm_handle_group group = {};
};

std::vector<double> rest_positions(const dfm_mesh* mesh) {
    dfm_mesh_info info = {};
    REQUIRE(dfm_mesh_get_info(mesh, &info) == DFM_OK);
    std::vector<double> xyz(3 * info.vertex_count);
    const dfm_vec3_output out = {xyz.data(), info.vertex_count, 0, DFM_SCALAR_FLOAT64};
    REQUIRE(dfm_mesh_read_positions(mesh, &out) == DFM_OK);
    return xyz;
}

// The newest frame's ROI positions, x y z per vertex.
std::vector<double> frame_positions(dfm_session* session, std::size_t roi_count,
                                    dfm_frame_info& info) {
    std::vector<double> xyz(3 * roi_count);
    const dfm_vec3_output out = {xyz.data(), roi_count, 0, DFM_SCALAR_FLOAT64};
    REQUIRE(dfm_session_read_roi_positions(session, &out, &info) == DFM_OK);
    return xyz;
}

double largest_difference(const std::vector<double>& a, const std::vector<double>& b) {
    REQUIRE(a.size() == b.size());
    double largest = 0.0;
    for (std::size_t i = 0; i < a.size(); ++i) largest = std::max(largest, std::abs(a[i] - b[i]));
    return largest;
}

void stage_drag(dfm_session* session) {
    double m[16];
    translation(0.3, 0.1, 0.0, m);
    REQUIRE(dfm_session_set_group_transform(session, 0, m) == DFM_OK);
}

}  // namespace

TEST_CASE("allocation failure: dfm_mesh_load survives every failed allocation") {
    const SweepLimb limb;
    const std::string file = (scratch_dir("sweep-load") / "limb.off").string();
    {
        Objects saving;
        saving.mesh = make_c_mesh(saving.context, limb.shape);
        REQUIRE(dfm_mesh_save(saving.mesh, file.c_str()) == DFM_OK);
    }
    const std::size_t points = sweep_allocation_failures([&](std::size_t k) {
        Objects o;
        dfm_result r = DFM_OK;
        {
            ArmedAllocationFailure armed(k);
            r = dfm_mesh_load(o.context, file.c_str(), &o.mesh);
        }
        if (r != DFM_OK) {
            CHECK(o.mesh == nullptr);
            REQUIRE(dfm_mesh_load(o.context, file.c_str(), &o.mesh) == DFM_OK);
        }
        dfm_mesh_info info = {};
        REQUIRE(dfm_mesh_get_info(o.mesh, &info) == DFM_OK);
        CHECK(info.vertex_count == limb.shape.vertex_count());
        return r;
    });
    MESSAGE("dfm_mesh_load: " << points << " allocation points exercised");
    CHECK(points > 0);
}

TEST_CASE(
    "allocation failure: dfm_roi_water_fill and dfm_roi_ball survive every failed allocation") {
    const SweepLimb limb;
    const auto sweep_roi = [&](const std::string& name, auto&& make_roi) {
        std::size_t expected = 0;
        const std::size_t points = sweep_allocation_failures([&](std::size_t k) {
            Objects o;
            o.mesh = make_c_mesh(o.context, limb.shape);
            dfm_result r = DFM_OK;
            {
                ArmedAllocationFailure armed(k);
                r = make_roi(o.mesh, &o.roi);
            }
            if (r != DFM_OK) {
                CHECK(o.roi == nullptr);
                REQUIRE(make_roi(o.mesh, &o.roi) == DFM_OK);
            }
            std::size_t count = 0;
            REQUIRE(dfm_roi_count(o.roi, &count) == DFM_OK);
            if (expected == 0) expected = count;
            CHECK(count == expected);
            return r;
        });
        MESSAGE(name << ": " << points << " allocation points exercised");
        CHECK(points > 0);
        CHECK(expected > limb.tip.size());
    };
    sweep_roi("dfm_roi_water_fill", [&](dfm_mesh* mesh, dfm_roi** out) {
        return dfm_roi_water_fill(mesh, limb.tip_centre, limb.middle, out, nullptr);
    });
    sweep_roi("dfm_roi_ball", [&](dfm_mesh* mesh, dfm_roi** out) {
        return dfm_roi_ball(mesh, limb.tip_centre, 0.4, out);
    });
}

TEST_CASE("allocation failure: dfm_session_create survives every failed allocation") {
    const SweepLimb limb;
    const std::size_t points = sweep_allocation_failures([&](std::size_t k) {
        Objects o;
        o.mesh = make_c_mesh(o.context, limb.shape);
        REQUIRE(dfm_roi_from_vertices(o.mesh, limb.region.data(), limb.region.size(), &o.roi) ==
                DFM_OK);
        const dfm_session_desc desc = o.session_desc(limb);
        dfm_result r = DFM_OK;
        {
            ArmedAllocationFailure armed(k);
            r = dfm_session_create(o.mesh, &desc, &o.session);
        }
        if (r != DFM_OK) {
            CHECK(o.session == nullptr);
            REQUIRE(dfm_session_create(o.mesh, &desc, &o.session) == DFM_OK);
        }
        stage_drag(o.session);
        std::uint64_t g = 0;
        REQUIRE(dfm_session_solve(o.session, &g) == DFM_OK);
        dfm_frame_info info = {};
        REQUIRE(dfm_session_poll(o.session, 0, &info, nullptr) == DFM_OK);
        CHECK(info.converged);
        return r;
    });
    MESSAGE("dfm_session_create: " << points << " allocation points exercised");
    CHECK(points > 0);
}

TEST_CASE("allocation failure: dfm_session_solve survives every failed allocation") {
    const SweepLimb limb;
    std::vector<double> reference;
    {
        Objects o;
        o.make_session(limb);
        stage_drag(o.session);
        REQUIRE(dfm_session_solve(o.session, nullptr) == DFM_OK);
        dfm_frame_info info = {};
        reference = frame_positions(o.session, limb.region.size(), info);
    }
    const std::size_t points = sweep_allocation_failures([&](std::size_t k) {
        Objects o;
        o.make_session(limb);
        dfm_frame_info start = {};
        const std::vector<double> start_positions =
            frame_positions(o.session, limb.region.size(), start);
        stage_drag(o.session);
        dfm_result r = DFM_OK;
        {
            ArmedAllocationFailure armed(k);
            r = dfm_session_solve(o.session, nullptr);
        }
        if (r != DFM_OK) {
            // Nothing lost: the newest frame is still the last good one.
            dfm_frame_info after = {};
            CHECK(frame_positions(o.session, limb.region.size(), after) == start_positions);
            CHECK(after.generation == start.generation);
            CHECK(after.checksum == start.checksum);
            REQUIRE(dfm_session_solve(o.session, nullptr) == DFM_OK);
        }
        dfm_frame_info solved = {};
        const std::vector<double> positions =
            frame_positions(o.session, limb.region.size(), solved);
        CHECK(solved.converged);
        CHECK(solved.status == DFM_OK);
        CHECK(largest_difference(positions, reference) < 1e-3);
        return r;
    });
    MESSAGE("dfm_session_solve: " << points << " allocation points exercised");
    // The solve reuses the buffers set up with the session, so running out
    // of memory mid-drag cannot fail it.
    CHECK(points == 0);
}

TEST_CASE("allocation failure: dfm_session_bake survives every failed allocation") {
    const SweepLimb limb;
    const std::size_t points = sweep_allocation_failures([&](std::size_t k) {
        Objects o;
        o.make_session(limb);
        const std::vector<double> rest = rest_positions(o.mesh);
        stage_drag(o.session);
        REQUIRE(dfm_session_solve(o.session, nullptr) == DFM_OK);
        dfm_result r = DFM_OK;
        {
            ArmedAllocationFailure armed(k);
            r = dfm_session_bake(o.session);
        }
        dfm_mesh_info info = {};
        if (r != DFM_OK) {
            // Nothing was changed: the rest pose and its history are as before.
            REQUIRE(dfm_mesh_get_info(o.mesh, &info) == DFM_OK);
            CHECK(info.bake_count == 0);
            CHECK(rest_positions(o.mesh) == rest);
            REQUIRE(dfm_session_bake(o.session) == DFM_OK);
        }
        REQUIRE(dfm_mesh_get_info(o.mesh, &info) == DFM_OK);
        CHECK(info.bake_count == 1);
        CHECK(largest_difference(rest_positions(o.mesh), rest) > 0.1);
        // The restarted session edits the baked pose.
        stage_drag(o.session);
        REQUIRE(dfm_session_solve(o.session, nullptr) == DFM_OK);
        REQUIRE(dfm_mesh_undo_bake(o.mesh) == DFM_OK);
        CHECK(rest_positions(o.mesh) == rest);
        return r;
    });
    MESSAGE("dfm_session_bake: " << points << " allocation points exercised");
    CHECK(points > 0);
}

}  // namespace dfm::test
