// sdk_bench [--model NAME] [--roi N] [--frames F] [--tolerance T] [--workers W]
//
// Uses only the public C API. Builds a ball ROI of at least N vertices
// (default 20000) on the model (default armadillo) with a small handle ball
// at its centre, then measures, on the host thread:
//   - dfm_session_create: how long the call takes to return, and how long
//     the set-up then runs on the context's worker (until dfm_session_wait
//     for generation 0 returns), over 5 sessions;
//   - submit alone on a small ROI (about 1000 vertices) whose context's
//     worker is idle, asleep for 2 ms before each submit: the cost of waking
//     it; and
//     the CPU the idle worker uses while it looks for work (other threads'
//     CPU time over 90 ms with nothing submitted, in percent of one core);
//   - set_group_transform + submit, submit alone, poll, read_roi_positions
//     (float) and read_positions (whole mesh), each timed per call while the
//     worker is busy solving;
//   - a 60 Hz drag of F frames (default 120), from a frame solved at the
//     path's first point: per frame, the latency from submitting new
//     targets to the first finished frame of that generation or newer (a
//     second thread blocks in dfm_session_wait);
//   - cancel and destroy issued 5 ms into a long solve, and destroy right
//     after create (during the set-up): time to return.
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "dualform/dualform.h"
#include "environment/host_environment.hpp"

namespace {

using Clock = std::chrono::steady_clock;

// CPU time of the calling thread: on a loaded machine the wall time of a
// short call is mostly other processes' turns.
double thread_cpu_ms() {
    timespec t{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
    return 1e3 * static_cast<double>(t.tv_sec) + 1e-6 * static_cast<double>(t.tv_nsec);
}

// CPU time of the whole process.
double process_cpu_ms() {
    timespec t{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return 1e3 * static_cast<double>(t.tv_sec) + 1e-6 * static_cast<double>(t.tv_nsec);
}

double ms_since(Clock::time_point t) {
    return std::chrono::duration<double, std::milli>(Clock::now() - t).count();
}

void check(dfm_result r, const char* what) {
    if (r == DFM_OK) return;
    std::fprintf(stderr, "sdk_bench: %s: %s: %s\n", what, dfm_result_name(r),
                 dfm_last_error_message());
    std::exit(1);
}

struct Stats {
    double p50 = 0, p90 = 0, p99 = 0, max = 0;
};

Stats stats_of(std::vector<double> v) {
    Stats s;
    if (v.empty()) return s;
    std::sort(v.begin(), v.end());
    auto at = [&](double q) { return v[std::min(v.size() - 1, std::size_t(q * v.size()))]; };
    s.p50 = at(0.5);
    s.p90 = at(0.9);
    s.p99 = at(0.99);
    s.max = v.back();
    return s;
}

std::string json(const char* name, const Stats& s, const char* unit) {
    char buffer[256];
    std::snprintf(buffer, sizeof buffer,
                  "\"%s_%s\": {\"p50\": %.3f, \"p90\": %.3f, \"p99\": %.3f, \"max\": %.3f}", name,
                  unit, s.p50, s.p90, s.p99, s.max);
    return buffer;
}

void translation(double x, double y, double z, double m[16]) {
    for (int i = 0; i < 16; ++i) m[i] = (i % 5 == 0) ? 1.0 : 0.0;
    m[12] = x;
    m[13] = y;
    m[14] = z;
}

struct Edit {
    dfm_mesh* mesh = nullptr;
    dfm_roi* roi = nullptr;
    std::vector<std::uint32_t> handle;
    std::size_t roi_size = 0;
    dfm_mesh_info info{};
};

dfm_session* start(const Edit& e, dfm_solver_settings solver, const dfm_roi* roi = nullptr) {
    const dfm_handle_group group = {e.handle.data(), e.handle.size()};
    dfm_session_desc desc = {};
    desc.struct_size = sizeof desc;
    desc.roi = roi != nullptr ? roi : e.roi;
    desc.groups = &group;
    desc.group_count = 1;
    desc.solver = solver;
    dfm_session* s = nullptr;
    check(dfm_session_create(e.mesh, &desc, &s), "dfm_session_create");
    return s;
}

}  // namespace

int main(int argc, char** argv) {
    std::string model = "model:armadillo";
    std::size_t roi_target = 20000;
    int frames = 120;
    double tolerance = 1e-5;
    std::uint32_t workers = 1;
    for (int i = 1; i + 1 < argc; i += 2) {
        const std::string flag = argv[i];
        if (flag == "--model") {
            model = argv[i + 1];
        } else if (flag == "--roi") {
            roi_target = std::strtoul(argv[i + 1], nullptr, 10);
        } else if (flag == "--frames") {
            frames = std::atoi(argv[i + 1]);
        } else if (flag == "--tolerance") {
            tolerance = std::atof(argv[i + 1]);
        } else if (flag == "--workers") {
            workers = static_cast<std::uint32_t>(std::strtoul(argv[i + 1], nullptr, 10));
        } else {
            std::fprintf(stderr,
                         "usage: sdk_bench [--model NAME] [--roi N] [--frames F] [--tolerance T] "
                         "[--workers W]\n");
            return 2;
        }
    }
    dfm_context* context = nullptr;
    const std::string models = dfm::tools::models_folder_from_environment().string();
    dfm_context_desc context_desc = {};
    context_desc.models_directory = models.c_str();
    context_desc.worker_count = workers;
    check(dfm_context_create(&context_desc, &context), "dfm_context_create");
    Edit e;
    check(dfm_mesh_load(context, model.c_str(), &e.mesh), "dfm_mesh_load");
    check(dfm_mesh_get_info(e.mesh, &e.info), "dfm_mesh_get_info");
    const std::uint32_t centre = 0;
    double lo = 0.0, hi = 2.0;
    for (int step = 0; step < 30; ++step) {
        const double mid = 0.5 * (lo + hi);
        dfm_roi* probe = nullptr;
        check(dfm_roi_ball(e.mesh, centre, mid, &probe), "dfm_roi_ball");
        std::size_t n = 0;
        dfm_roi_count(probe, &n);
        dfm_roi_destroy(probe);
        (n >= roi_target ? hi : lo) = mid;
    }
    check(dfm_roi_ball(e.mesh, centre, hi, &e.roi), "dfm_roi_ball");
    dfm_roi_count(e.roi, &e.roi_size);
    dfm_roi* handle = nullptr;
    check(dfm_roi_ball(e.mesh, centre, 0.02, &handle), "dfm_roi_ball");
    std::size_t handle_size = 0;
    dfm_roi_count(handle, &handle_size);
    e.handle.resize(handle_size);
    check(dfm_roi_read(handle, e.handle.data(), handle_size), "dfm_roi_read");
    dfm_roi_destroy(handle);

    const double diag = e.info.diagonal;
    dfm_solver_settings drag = {};
    drag.tolerance = tolerance;
    std::vector<double> create_return_ms, create_cpu_ms, setup_ms;
    for (int round = 0; round < 5; ++round) {
        const auto t = Clock::now();
        const double cpu = thread_cpu_ms();
        dfm_session* fresh = start(e, drag);
        create_cpu_ms.push_back(thread_cpu_ms() - cpu);
        create_return_ms.push_back(ms_since(t));
        check(dfm_session_wait(fresh, 0, -1, nullptr), "wait for the set-up");
        setup_ms.push_back(ms_since(t));
        dfm_session_destroy(fresh);
    }
    dfm_session* s = start(e, drag);
    check(dfm_session_wait(s, 0, -1, nullptr), "wait for the set-up");

    // Submit with the worker idle: a small ROI, solved and asleep each time.
    std::vector<double> submit_idle_us, idle_poll_cpu_percent;
    {
        dfm_roi* small = nullptr;
        check(dfm_roi_ball(e.mesh, centre, 0.0, &small), "dfm_roi_ball");
        for (std::size_t n = 0; n < 1000;) {
            dfm_roi* grown = nullptr;
            check(dfm_roi_grow(small, 1, &grown), "dfm_roi_grow");
            dfm_roi_destroy(small);
            small = grown;
            dfm_roi_count(small, &n);
        }
        dfm_session* idle = start(e, drag, small);
        check(dfm_session_wait(idle, 0, -1, nullptr), "wait for the set-up");
        for (int i = 0; i < 2000; ++i) {
            double m[16];
            translation(0.001 * diag * (i % 50), 0.0, 0.0, m);
            check(dfm_session_set_group_transform(idle, 0, m), "set_group_transform");
            std::this_thread::sleep_for(std::chrono::milliseconds(2));
            std::uint64_t g = 0;
            const auto t = Clock::now();
            check(dfm_session_submit(idle, &g), "submit");
            submit_idle_us.push_back(1000.0 * ms_since(t));
            check(dfm_session_wait(idle, g, -1, nullptr), "wait");
        }
        // What the worker's looking for work costs: 90 ms after a solve,
        // inside its 100 ms window, with nothing submitted.
        for (int round = 0; round < 10; ++round) {
            std::uint64_t g = 0;
            check(dfm_session_submit(idle, &g), "submit");
            check(dfm_session_wait(idle, g, -1, nullptr), "wait");
            const auto t = Clock::now();
            const double cpu = process_cpu_ms() - thread_cpu_ms();
            std::this_thread::sleep_for(std::chrono::milliseconds(90));
            idle_poll_cpu_percent.push_back(100.0 * (process_cpu_ms() - thread_cpu_ms() - cpu) /
                                            ms_since(t));
        }
        dfm_session_destroy(idle);
        dfm_roi_destroy(small);
    }

    // Per-call costs while the worker is busy.
    std::vector<float> roi_xyz(3 * e.roi_size), mesh_xyz(3 * e.info.vertex_count);
    const dfm_vec3_output roi_out = {roi_xyz.data(), e.roi_size, 0, DFM_SCALAR_FLOAT32};
    const dfm_vec3_output mesh_out = {mesh_xyz.data(), e.info.vertex_count, 0, DFM_SCALAR_FLOAT32};
    std::vector<double> submit_us, submit_busy_us, poll_us, read_roi_us, read_mesh_us, view_us;
    for (int i = 0; i < 2000; ++i) {
        double m[16];
        translation(0.05 * diag * std::sin(0.01 * i), 0.02 * diag, 0.0, m);
        auto t = Clock::now();
        check(dfm_session_set_group_transform(s, 0, m), "set_group_transform");
        std::uint64_t g = 0;
        const auto submit_start = Clock::now();
        check(dfm_session_submit(s, &g), "submit");
        submit_busy_us.push_back(1000.0 * ms_since(submit_start));
        submit_us.push_back(1000.0 * ms_since(t));
        dfm_frame_info info{};
        t = Clock::now();
        check(dfm_session_poll(s, 0, &info, nullptr), "poll");
        poll_us.push_back(1000.0 * ms_since(t));
        t = Clock::now();
        check(dfm_session_read_roi_positions(s, &roi_out, nullptr), "read_roi_positions");
        read_roi_us.push_back(1000.0 * ms_since(t));
        t = Clock::now();
        dfm_frame_view view{};
        check(dfm_session_acquire_frame(s, &view, nullptr), "acquire_frame");
        check(dfm_session_release_frame(s), "release_frame");
        view_us.push_back(1000.0 * ms_since(t));
        if (i % 10 == 0) {
            t = Clock::now();
            check(dfm_session_read_positions(s, &mesh_out, nullptr), "read_positions");
            read_mesh_us.push_back(1000.0 * ms_since(t));
        }
        std::this_thread::sleep_for(std::chrono::microseconds(200));
    }
    check(dfm_session_cancel(s), "cancel");

    // A 60 Hz drag: latency from submit to the first finished frame >= it.
    std::vector<Clock::time_point> submitted(static_cast<std::size_t>(frames) + 2);
    std::vector<double> latency_ms, finished_iterations, finished_solve_ms;
    std::mutex latency_mutex;
    std::atomic<std::uint64_t> last{0};
    std::uint64_t first_generation = 0;
    // The handle's path; the drag starts from a frame solved at its first
    // point, so that every latency is that of a drag step, not of a jump.
    const auto drag_pose = [diag](int f, double m[16]) {
        const double t = f / 60.0;
        translation(0.05 * diag * std::sin(3.0 * t), 0.02 * diag, 0.02 * diag * std::cos(2.0 * t),
                    m);
    };
    {
        double m[16];
        drag_pose(0, m);
        check(dfm_session_set_group_transform(s, 0, m), "set_group_transform");
        check(dfm_session_solve(s, &first_generation), "solve");
    }
    std::atomic<bool> dragging{true};
    std::thread monitor([&] {
        std::uint64_t seen = first_generation;
        while (dragging.load() || seen < last.load()) {
            const std::uint64_t wanted = seen + 1;
            if (wanted > last.load()) {
                std::this_thread::sleep_for(std::chrono::microseconds(100));
                continue;
            }
            dfm_frame_info info{};
            if (dfm_session_wait(s, wanted, 5000, &info) != DFM_OK) break;
            const auto now = Clock::now();
            std::lock_guard<std::mutex> lock(latency_mutex);
            for (std::uint64_t g = wanted; g <= info.generation; ++g) {
                latency_ms.push_back(std::chrono::duration<double, std::milli>(
                                         now - submitted[g - first_generation - 1])
                                         .count());
            }
            finished_iterations.push_back(info.iterations);
            finished_solve_ms.push_back(info.solve_ms);
            seen = info.generation;
        }
    });
    auto tick = Clock::now();
    for (int f = 0; f < frames; ++f) {
        double m[16];
        drag_pose(f + 1, m);
        check(dfm_session_set_group_transform(s, 0, m), "set_group_transform");
        std::uint64_t g = 0;
        submitted[static_cast<std::size_t>(f)] = Clock::now();
        check(dfm_session_submit(s, &g), "submit");
        last = g;
        tick += std::chrono::microseconds(16667);
        std::this_thread::sleep_until(tick);
    }
    dragging = false;
    monitor.join();

    // Cancel and destroy, 5 ms into a solve that would run long.
    dfm_solver_settings slow = {};
    slow.tolerance = 1e-14;
    slow.max_iterations = 100000;
    std::vector<double> cancel_ms, destroy_ms;
    check(dfm_session_set_solver(s, &slow), "set_solver");
    for (int round = 0; round < 5; ++round) {
        double m[16];
        translation(0.1 * diag * (round + 1) / 5.0, 0.0, 0.0, m);
        check(dfm_session_set_group_transform(s, 0, m), "set_group_transform");
        std::uint64_t g = 0;
        check(dfm_session_submit(s, &g), "submit");
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
        const auto t = Clock::now();
        check(dfm_session_cancel(s), "cancel");
        cancel_ms.push_back(ms_since(t));
    }
    dfm_session_destroy(s);
    std::vector<double> destroy_in_setup_ms;
    for (int round = 0; round < 3; ++round) {
        dfm_session* early = start(e, slow);
        const auto t = Clock::now();
        dfm_session_destroy(early);
        destroy_in_setup_ms.push_back(ms_since(t));
    }
    for (int round = 0; round < 3; ++round) {
        dfm_session* victim = start(e, slow);
        check(dfm_session_wait(victim, 0, -1, nullptr), "wait for the set-up");
        double m[16];
        translation(0.1 * diag, 0.0, 0.0, m);
        check(dfm_session_set_group_transform(victim, 0, m), "set_group_transform");
        std::uint64_t g = 0;
        check(dfm_session_submit(victim, &g), "submit");
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
        const auto t = Clock::now();
        dfm_session_destroy(victim);
        destroy_ms.push_back(ms_since(t));
    }

    std::printf(
        "{\"model\": \"%s\", \"vertices\": %zu, \"roi\": %zu, \"handle\": %zu, "
        "\"tolerance\": %g, \"drag_frames\": %d, \"workers\": %u",
        model.c_str(), e.info.vertex_count, e.roi_size, e.handle.size(), tolerance, frames,
        static_cast<unsigned>(workers));
    const std::string fields[] = {
        json("create_return", stats_of(create_return_ms), "ms"),
        json("create_cpu", stats_of(create_cpu_ms), "ms"),
        json("setup_on_worker", stats_of(setup_ms), "ms"),
        json("submit_idle", stats_of(submit_idle_us), "us"),
        json("idle_worker_cpu", stats_of(idle_poll_cpu_percent), "percent"),
        json("submit_busy", stats_of(submit_busy_us), "us"),
        json("set_transform_submit", stats_of(submit_us), "us"),
        json("poll", stats_of(poll_us), "us"),
        json("read_roi_positions", stats_of(read_roi_us), "us"),
        json("read_positions", stats_of(read_mesh_us), "us"),
        json("acquire_release_frame", stats_of(view_us), "us"),
        json("drag_latency", stats_of(latency_ms), "ms"),
        json("finished_solve", stats_of(finished_solve_ms), "ms"),
        json("finished_solve", stats_of(finished_iterations), "iterations"),
        json("cancel", stats_of(cancel_ms), "ms"),
        json("destroy", stats_of(destroy_ms), "ms"),
        json("destroy_during_setup", stats_of(destroy_in_setup_ms), "ms"),
    };
    for (const std::string& field : fields) std::printf(",\n %s", field.c_str());
    std::printf("}\n");
    dfm_roi_destroy(e.roi);
    dfm_mesh_destroy(e.mesh);
    dfm_context_destroy(context);
    return 0;
}
