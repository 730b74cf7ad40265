// crowd: a herd of cows on one mesh, each animating one limb (its tail or its
// front leg) through a session of its own, all sessions on one context, in
// a 60 Hz fixed-step loop. One work mode per run: the context's own worker
// threads (pool), the game's job system (jobs, job_system.hpp), or no
// thread at all (stepped: the loop advances the work within a budget each
// tick).
//
// usage: crowd [--mode pool|jobs|stepped] [--cows N] [--ticks N] [--workers N]
//              [--budget-us N] [--png OUT]
//
// The last line printed is one JSON object: the age of each cow's newest
// finished result and the longest wait between two, the finished frames (in
// all, and the fewest of one cow), how many cows' last targets were solved
// after the loop, the process's threads, and each session's memory and
// set-up time.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "../common/sample_environment.h"
#include "dualform/dualform.h"
#include "herd.hpp"
#include "job_system.hpp"
#include "picture.hpp"

namespace {

using Clock = std::chrono::steady_clock;

struct Options {
    dfm_work_mode mode = DFM_WORK_POOL;
    std::string mode_name = "pool";
    int cows = 64;
    int ticks = 600;
    int workers = 2;
    int budget_us = 8000;  // stepped: the tick's share of Dualform's work
    std::string png;
};

bool parse(int argc, char** argv, Options& o) {
    for (int i = 1; i < argc; ++i) {
        const std::string arg = argv[i];
        if (i + 1 >= argc) return false;
        const char* value = argv[++i];
        if (arg == "--mode") {
            o.mode_name = value;
            if (o.mode_name == "pool") {
                o.mode = DFM_WORK_POOL;
            } else if (o.mode_name == "jobs") {
                o.mode = DFM_WORK_JOB_SYSTEM;
            } else if (o.mode_name == "stepped") {
                o.mode = DFM_WORK_HOST_STEPPED;
            } else {
                return false;
            }
        } else if (arg == "--cows") {
            o.cows = std::atoi(value);
        } else if (arg == "--ticks") {
            o.ticks = std::atoi(value);
        } else if (arg == "--workers") {
            o.workers = std::atoi(value);
        } else if (arg == "--budget-us") {
            o.budget_us = std::atoi(value);
        } else if (arg == "--png") {
            o.png = value;
        } else {
            return false;
        }
    }
    return o.cows > 0 && o.ticks > 0 && o.workers > 0 && o.budget_us > 0;
}

bool ok(dfm_result result, const char* call) {
    if (result == DFM_OK) return true;
    std::fprintf(stderr, "crowd: %s: %s: %s\n", call, dfm_result_name(result),
                 dfm_last_error_message());
    return false;
}

template <class T>
T percentile(std::vector<T> v, double q) {
    std::sort(v.begin(), v.end());
    return v[std::min(v.size() - 1, static_cast<std::size_t>(q * static_cast<double>(v.size())))];
}

// The process's threads, as the kernel counts them.
int process_threads() {
    std::ifstream status("/proc/self/status");
    std::string line;
    while (std::getline(status, line)) {
        if (line.rfind("Threads:", 0) == 0) return std::atoi(line.c_str() + 8);
    }
    return -1;
}

// What the loop measured.
struct Figures {
    std::vector<int> ages;  // each cow's, each tick
    std::vector<double> host_ms;
    int finished_frames = 0;
    int last_targets_solved = 0;  // cows whose last submitted targets were solved
};

// The fixed-step loop: every cow's limb moves every tick, and the newest
// results are picked up (and placed in the picture when one is drawn).
bool run(const Options& o, dfm_context* context, double diagonal, std::vector<herd::Cow>& cows,
         Picture* picture, Figures& figures) {
    const auto start = Clock::now();
    for (int tick = 0; tick < o.ticks; ++tick) {
        const auto tick_start = Clock::now();
        const double t = tick / 60.0;
        for (herd::Cow& cow : cows) {
            double m[16];
            herd::transform_at(cow, t, diagonal, m);
            std::uint64_t generation = 0;
            if (!ok(dfm_session_set_group_transform(cow.session, 0, m), "set_transform") ||
                !ok(dfm_session_submit(cow.session, &generation), "submit")) {
                return false;
            }
            cow.submitted_at.resize(generation + 1, tick);
        }
        if (o.mode == DFM_WORK_HOST_STEPPED &&
            !ok(dfm_context_step(context, static_cast<std::uint64_t>(o.budget_us), nullptr),
                "dfm_context_step")) {
            return false;
        }
        for (std::size_t c = 0; c < cows.size(); ++c) {
            herd::Cow& cow = cows[c];
            dfm_frame_info info = {};
            bool is_new = false;
            if (!ok(dfm_session_poll(cow.session, cow.shown, &info, &is_new), "poll")) return false;
            if (is_new && picture != nullptr) {
                dfm_frame_view view = {};
                if (dfm_session_acquire_frame(cow.session, &view, &info) == DFM_OK) {
                    picture->place(c, view);
                    dfm_session_release_frame(cow.session);
                }
            }
            if (is_new && !info.partial && info.status == DFM_OK) {
                cow.longest_wait = std::max(cow.longest_wait, tick - cow.last_finished_tick);
                cow.last_finished_tick = tick;
                cow.shown = info.generation;
                ++cow.finished;
                ++figures.finished_frames;
            }
            figures.ages.push_back(tick - cow.submitted_at[cow.shown]);
        }
        figures.host_ms.push_back(
            std::chrono::duration<double, std::milli>(Clock::now() - tick_start).count());
        std::this_thread::sleep_until(start + std::chrono::microseconds(16667) * (tick + 1));
    }
    for (herd::Cow& cow : cows) {
        cow.longest_wait = std::max(cow.longest_wait, o.ticks - cow.last_finished_tick);
    }
    // The newest targets win: each cow's last ones are solved, whatever was
    // skipped on the way (the wait runs the work where the host steps it).
    for (const herd::Cow& cow : cows) {
        const std::uint64_t last = cow.submitted_at.size() - 1;
        dfm_frame_info info = {};
        if (!ok(dfm_session_wait(cow.session, last, -1, &info), "wait")) return false;
        if (info.generation == last && info.status == DFM_OK) ++figures.last_targets_solved;
    }
    return true;
}

}  // namespace

int main(int argc, char** argv) {
    Options options;
    if (!parse(argc, argv, options)) {
        std::fprintf(stderr,
                     "usage: crowd [--mode pool|jobs|stepped] [--cows N] [--ticks N] "
                     "[--workers N] [--budget-us N] [--png OUT]\n");
        return 2;
    }
    const int host_threads =
        process_threads() + (options.mode == DFM_WORK_JOB_SYSTEM ? options.workers : 0);
    std::unique_ptr<JobSystem> jobs;
    if (options.mode == DFM_WORK_JOB_SYSTEM) {
        jobs = std::make_unique<JobSystem>(static_cast<std::size_t>(options.workers));
    }
    char models[4096];
    dfm_context_desc context_desc = {};
    context_desc.struct_size = sizeof context_desc;
    context_desc.models_directory = sample_models_folder(models, sizeof models);
    context_desc.work_mode = options.mode;
    context_desc.worker_count =
        options.mode == DFM_WORK_HOST_STEPPED ? 1 : static_cast<std::uint32_t>(options.workers);
    if (jobs) context_desc.job_system = jobs->hooks();

    dfm_context* context = nullptr;
    dfm_mesh* mesh = nullptr;
    dfm_mesh_info info = {};
    herd::Regions regions;
    std::vector<herd::Cow> cows;
    Picture picture;
    Figures figures;
    std::vector<double> setup_ms;
    std::vector<std::size_t> session_bytes;
    dfm_session_memory largest = {};
    int status = 1;
    if (ok(dfm_context_create(&context_desc, &context), "dfm_context_create") &&
        ok(dfm_mesh_load(context, "model:cow", &mesh), "dfm_mesh_load") &&
        ok(dfm_mesh_get_info(mesh, &info), "dfm_mesh_get_info") &&
        herd::make_regions(mesh, regions) &&
        herd::make_cows(mesh, regions, static_cast<std::size_t>(options.cows), cows) &&
        (options.png.empty() || picture.lay_out(mesh, regions, cows))) {
        // The set-ups run as the context's work; the first frames wait for them.
        bool set_up = true;
        for (const herd::Cow& cow : cows) {
            dfm_solve_report report = {};
            set_up = set_up && ok(dfm_session_wait(cow.session, 0, -1, nullptr), "wait") &&
                     ok(dfm_session_get_solve_report(cow.session, &report, nullptr), "report");
            setup_ms.push_back(report.setup_ms);
        }
        if (set_up && run(options, context, info.diagonal, cows,
                          options.png.empty() ? nullptr : &picture, figures)) {
            status = 0;
        }
    }
    const int threads = process_threads();
    for (const herd::Cow& cow : cows) {
        dfm_session_memory memory = {};
        dfm_session_get_memory(cow.session, &memory);
        session_bytes.push_back(memory.total);
        if (memory.total > largest.total) largest = memory;
    }
    if (status == 0 && !options.png.empty() &&
        !picture.write_png(options.png.c_str(), 640, 360, sample_validation())) {
        status = 1;
    }
    if (status == 0) {
        int longest_wait = 0;
        int fewest_finished = cows.empty() ? 0 : cows.front().finished;
        for (const herd::Cow& cow : cows) {
            longest_wait = std::max(longest_wait, cow.longest_wait);
            fewest_finished = std::min(fewest_finished, cow.finished);
        }
        std::printf(
            "{\"mode\": \"%s\", \"cows\": %zu, \"workers\": %u, \"ticks\": %d, "
            "\"result_age_ticks\": {\"p50\": %d, \"p99\": %d, \"max\": %d}, "
            "\"longest_wait_ticks\": %d, \"finished_frames\": %d, "
            "\"fewest_finished_frames\": %d, \"last_targets_solved\": %d, "
            "\"threads\": {\"process\": %d, \"host\": %d, \"library\": %d}, "
            "\"session_bytes\": {\"p50\": %zu, \"max\": %zu, \"largest\": {\"factor\": %zu, "
            "\"normal_matrix\": %zu, \"iteration\": %zu, \"frames\": %zu, \"staging\": %zu}}, "
            "\"setup_ms\": {\"p50\": %.3f, \"max\": %.3f}, "
            "\"host_tick_ms\": {\"p50\": %.3f, \"p99\": %.3f}}\n",
            options.mode_name.c_str(), cows.size(), context_desc.worker_count, options.ticks,
            percentile(figures.ages, 0.5), percentile(figures.ages, 0.99),
            percentile(figures.ages, 1.0), longest_wait, figures.finished_frames, fewest_finished,
            figures.last_targets_solved, threads, host_threads, threads - host_threads,
            percentile(session_bytes, 0.5), percentile(session_bytes, 1.0), largest.factor,
            largest.normal_matrix, largest.iteration, largest.frames, largest.staging,
            percentile(setup_ms, 0.5), percentile(setup_ms, 1.0), percentile(figures.host_ms, 0.5),
            percentile(figures.host_ms, 0.99));
    }
    herd::destroy_cows(cows);
    herd::destroy_regions(regions);
    dfm_mesh_destroy(mesh);
    // The context first: after it returns Dualform hands the job system nothing.
    dfm_context_destroy(context);
    jobs.reset();
    return status;
}
