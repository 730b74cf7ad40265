#include <doctest/doctest.h>

#include <string>

#include "dualform/json_reader.hpp"
#include "support/run_process.hpp"

using namespace dfm;

namespace {

double number_at(const cli::JsonValue& object, const char* key, const char* field = nullptr) {
    const cli::JsonMember* member = object.find(key);
    REQUIRE_MESSAGE(member != nullptr, key);
    if (field == nullptr) return member->value.number;
    const cli::JsonMember* inner = member->value.find(field);
    REQUIRE_MESSAGE(inner != nullptr, key << "." << field);
    return inner->value.number;
}

}  // namespace

// 600 frames of the cow's tail shaking and leg stepping, headless on
// lavapipe with the validation layer on (the sample fails on any message).
// What it shows is at most a few frames old, and its own per-frame work is
// a small part of a frame (the median, robust to a loaded machine). The p99
// goal, under 2 ms, depends on the machine's load: it is measured in
// docs/benchmarks.md, and the line printed here shows it; a test asserts
// behaviour, never a tail latency.
TEST_CASE("game loop: 600 frames, the host never waits, results stay fresh") {
    const test::ProcessResult run =
        test::run_process(DUALFORM_GAME_LOOP, {"--frames", "600", "--model", "model:cow"});
    INFO(run.err);
    REQUIRE(run.exit_code == 0);
    const std::size_t last_line = run.out.find_last_of('\n', run.out.size() - 2);
    const std::string line = run.out.substr(last_line == std::string::npos ? 0 : last_line + 1);
    cli::JsonValue report;
    REQUIRE_MESSAGE(cli::parse_json(line, "game_loop output", report).is_ok(), line);
    MESSAGE(line);
    CHECK(number_at(report, "frames") == 600);
    CHECK(number_at(report, "results_received") >= 600);
    CHECK(number_at(report, "result_age_frames", "max") <= 3);
    CHECK(number_at(report, "host_frame_ms", "p50") < 2.0);
}
