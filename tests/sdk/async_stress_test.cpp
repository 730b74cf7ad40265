#include <doctest/doctest.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <thread>
#include <vector>

#include "dualform/dualform.h"
#include "sdk/sdk_fixture.hpp"

using namespace dfm::test;

// One host thread moves the handles at 1 kHz for 5 seconds while another
// reads every frame it can: no frame is torn (its bytes match the checksum
// the worker computed as it wrote it), generations never go back, and once
// the motion stops the newest targets' finished result arrives. Run under
// ThreadSanitizer by `tools/test tsan`.
TEST_CASE(
    "async: 1 kHz targets against a concurrent reader: no torn frame and the newest arrives") {
    LimbEdit limb(48, 120);
    std::size_t count = 0;
    REQUIRE(dfm_roi_count(limb.roi, &count) == DFM_OK);

    std::atomic<bool> moving{true};
    std::atomic<std::uint64_t> last_submitted{0};
    std::size_t frames_read = 0, torn = 0, backwards = 0, partial = 0;
    std::thread reader([&] {
        std::vector<double> xyz(3 * count);
        const dfm_vec3_output out = {xyz.data(), count, 0, DFM_SCALAR_FLOAT64};
        std::uint64_t previous = 0;
        while (moving.load()) {
            dfm_frame_info info = {};
            if (dfm_session_read_roi_positions(limb.session, &out, &info) != DFM_OK) break;
            ++frames_read;
            if (fnv1a(xyz.data(), xyz.size() * sizeof(double)) != info.checksum) ++torn;
            if (info.generation < previous) ++backwards;
            if (info.partial) ++partial;
            previous = info.generation;
            std::this_thread::sleep_for(std::chrono::microseconds(300));
        }
    });

    const auto start = std::chrono::steady_clock::now();
    std::size_t submits = 0;
    for (auto tick = start; tick - start < std::chrono::seconds(5);
         tick += std::chrono::milliseconds(1)) {
        const double t = std::chrono::duration<double>(tick - start).count();
        double m[16];
        translation(0.3 * std::sin(6.0 * t), 0.1 * std::sin(4.0 * t), 0.0, m);
        REQUIRE(dfm_session_set_group_transform(limb.session, 0, m) == DFM_OK);
        std::uint64_t g = 0;
        REQUIRE(dfm_session_submit(limb.session, &g) == DFM_OK);
        last_submitted = g;
        ++submits;
        std::this_thread::sleep_until(tick + std::chrono::milliseconds(1));
    }
    const std::uint64_t newest = last_submitted.load();
    dfm_frame_info final_info = {};
    REQUIRE_MESSAGE(dfm_session_wait(limb.session, newest, 60000, &final_info) == DFM_OK,
                    last_error());
    moving = false;
    reader.join();

    MESSAGE("submits " << submits << ", frames read " << frames_read << " (" << partial
                       << " partial), final generation " << final_info.generation);
    CHECK(frames_read > 100);
    CHECK(torn == 0);
    CHECK(backwards == 0);
    CHECK(final_info.generation == newest);
    CHECK_FALSE(final_info.partial);
    CHECK(final_info.status == DFM_OK);
    std::vector<double> xyz(3 * count);
    const dfm_vec3_output out = {xyz.data(), count, 0, DFM_SCALAR_FLOAT64};
    dfm_frame_info info = {};
    REQUIRE(dfm_session_read_roi_positions(limb.session, &out, &info) == DFM_OK);
    CHECK(info.generation == newest);
    CHECK(fnv1a(xyz.data(), xyz.size() * sizeof(double)) == info.checksum);
}

TEST_CASE("async: cancel and destroy in the middle of solves return and leave no race") {
    dfm_solver_settings solver = {};
    solver.tolerance = 1e-13;
    solver.max_iterations = 1000000;
    LimbEdit limb(24, 40, solver);
    for (int round = 0; round < 5; ++round) {
        double m[16];
        translation(0.1 * round + 0.2, 0.0, 0.05 * round, m);
        REQUIRE(dfm_session_set_group_transform(limb.session, 0, m) == DFM_OK);
        std::uint64_t g = 0;
        REQUIRE(dfm_session_submit(limb.session, &g) == DFM_OK);
        std::this_thread::sleep_for(std::chrono::milliseconds(2));
        REQUIRE(dfm_session_cancel(limb.session) == DFM_OK);
        const dfm_result waited = dfm_session_wait(limb.session, g, 0, nullptr);
        CHECK((waited == DFM_OK || waited == DFM_ERROR_CANCELLED));
    }
    double m[16];
    translation(0.5, 0.0, 0.0, m);
    REQUIRE(dfm_session_set_group_transform(limb.session, 0, m) == DFM_OK);
    std::uint64_t g = 0;
    REQUIRE(dfm_session_submit(limb.session, &g) == DFM_OK);
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
    dfm_session_destroy(limb.session);
    limb.session = nullptr;
}
