#include <doctest/doctest.h>

#include <png.h>

#include <string>

#include "json/json_reader.hpp"
#include "sample_report.hpp"
#include "support/run_process.hpp"
#include "support/test_files.hpp"

using namespace dfm;
using dfm::test::number_at;

namespace {

// Runs the crowd sample and returns its last line, parsed.
json::JsonValue run_crowd(const std::vector<std::string>& arguments) {
    const test::ProcessResult run = test::run_process(DUALFORM_CROWD, arguments);
    INFO(run.err);
    REQUIRE(run.exit_code == 0);
    const std::size_t last_line = run.out.find_last_of('\n', run.out.size() - 2);
    const std::string line = run.out.substr(last_line == std::string::npos ? 0 : last_line + 1);
    json::JsonValue report;
    REQUIRE_MESSAGE(json::parse_json(line, "crowd output", report).is_ok(), line);
    MESSAGE(line);
    return report;
}

}  // namespace

// 64 cows, each a session of its own on one mesh, all on one context with
// two workers, animated every tick of 600 at 60 Hz, headless, in each work
// mode. The library's threads are the pool's two, or none with the host's
// job system or stepping. Sessions take turns, so none starves: the cow
// that finished the fewest frames finished at least half as many as the
// mean, and every cow's last targets are solved (the newest win). How fresh
// the results are depends on the machine: the sample prints the ages, and
// the test does not assert on them (docs/benchmarks.md has the figures).
TEST_CASE("crowd: 64 sessions on one context in each work mode, none starving") {
    struct Expected {
        const char* mode;
        double library_threads;
    };
    for (const Expected& e : {Expected{"pool", 2}, Expected{"jobs", 0}, Expected{"stepped", 0}}) {
        CAPTURE(e.mode);
        const json::JsonValue report = run_crowd({"--mode", e.mode, "--ticks", "600"});
        CHECK(number_at(report, "cows") == 64);
        CHECK(number_at(report, "ticks") == 600);
        CHECK(number_at(report, "threads", "library") == e.library_threads);
        const double fewest = number_at(report, "fewest_finished_frames");
        CHECK(fewest >= 1);
        CHECK(fewest >= 0.5 * number_at(report, "finished_frames") / 64);
        CHECK(number_at(report, "last_targets_solved") == 64);
    }
}

TEST_CASE("crowd: the herd is drawn in one picture") {
    const std::string png = (test::scratch_dir("crowd") / "crowd.png").string();
    run_crowd({"--cows", "16", "--ticks", "30", "--png", png});
    png_image image = {};
    image.version = PNG_IMAGE_VERSION;
    REQUIRE_MESSAGE(png_image_begin_read_from_file(&image, png.c_str()) != 0, png);
    CHECK(image.width == 640);
    CHECK(image.height == 360);
    png_image_free(&image);
}
