#include <doctest/doctest.h>

#include <algorithm>
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
            if (fnv1a_words(xyz.data(), xyz.size()) != info.checksum) ++torn;
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
    CHECK(fnv1a_words(xyz.data(), xyz.size()) == info.checksum);
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

// Three host threads stage and submit to one session while a fourth holds
// and releases frames: the header allows any of these calls at once. Each
// submit hands the worker exactly what was staged under the staging lock
// (ThreadSanitizer watches the copy), generations are unique and the last
// one's finished frame arrives.
TEST_CASE("async: three threads submit and poll one session while another acquires frames") {
    LimbEdit limb(16, 24);
    constexpr int rounds = 3000;
    std::atomic<bool> running{true};
    std::atomic<int> failures{0};
    std::vector<std::vector<std::uint64_t>> generations(3);
    // The submitters start once the viewer has made its first read, so the
    // rounds overlap its reads even when the scheduler starts it late.
    std::atomic<bool> viewing{false};
    std::size_t held = 0, torn = 0;
    std::thread viewer([&] {
        while (running.load()) {
            dfm_frame_view view = {};
            dfm_frame_info info = {};
            const dfm_result acquired = dfm_session_acquire_frame(limb.session, &view, &info);
            viewing = true;
            if (acquired != DFM_OK) continue;
            ++held;
            if (fnv1a_words(view.roi_positions_f64, 3 * view.roi_count) != info.checksum) {
                ++torn;
            }
            if (dfm_session_release_frame(limb.session) != DFM_OK) ++failures;
        }
    });
    std::vector<std::thread> submitters;
    for (int t = 0; t < 3; ++t) {
        submitters.emplace_back([&, t] {
            while (!viewing.load()) std::this_thread::yield();
            for (int i = 0; i < rounds; ++i) {
                double m[16];
                translation(0.001 * (i % 200) * (t + 1), 0.0, 0.0, m);
                std::uint64_t g = 0;
                dfm_frame_info info = {};
                if (dfm_session_set_group_transform(limb.session, 0, m) != DFM_OK ||
                    dfm_session_submit(limb.session, &g) != DFM_OK ||
                    dfm_session_poll(limb.session, g, &info, nullptr) != DFM_OK) {
                    ++failures;
                    return;
                }
                generations[t].push_back(g);
            }
        });
    }
    for (std::thread& t : submitters) t.join();
    std::uint64_t newest = 0;
    std::vector<std::uint64_t> all;
    for (const auto& list : generations) {
        all.insert(all.end(), list.begin(), list.end());
        for (std::uint64_t g : list) newest = std::max(newest, g);
    }
    dfm_frame_info final_info = {};
    REQUIRE_MESSAGE(dfm_session_wait(limb.session, newest, 60000, &final_info) == DFM_OK,
                    last_error());
    running = false;
    viewer.join();
    CHECK(failures == 0);
    CHECK(torn == 0);
    CHECK(held > 0);
    std::sort(all.begin(), all.end());
    CHECK(std::adjacent_find(all.begin(), all.end()) == all.end());
    CHECK(all.size() == 3u * rounds);
    CHECK(final_info.generation == newest);
}
