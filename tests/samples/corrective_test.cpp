#include <doctest/doctest.h>

#include <png.h>

#include <glm/geometric.hpp>

#include <filesystem>
#include <string>
#include <vector>

#include "json/json_reader.hpp"
#include "mesh/load.hpp"
#include "sample_report.hpp"
#include "support/run_process.hpp"
#include "support/test_files.hpp"

using namespace dfm;
using dfm::test::number_at;

namespace {

// Runs the corrective sample and returns its last line, parsed.
json::JsonValue run_corrective(const std::vector<std::string>& arguments, bool window = false) {
    std::vector<std::string> command = arguments;
    std::string program = DUALFORM_CORRECTIVE;
    if (window) {
        command.insert(command.begin(), {"-a", "-s", "-screen 0 1024x768x24", program});
        program = DUALFORM_XVFB_RUN;
    }
    const test::ProcessResult run = test::run_process(program, command);
    INFO(run.err);
    REQUIRE(run.exit_code == 0);
    const std::size_t last_line = run.out.find_last_of('\n', run.out.size() - 2);
    const std::string line = run.out.substr(last_line == std::string::npos ? 0 : last_line + 1);
    json::JsonValue report;
    REQUIRE_MESSAGE(json::parse_json(line, "corrective output", report).is_ok(), line);
    MESSAGE(line);
    return report;
}

mesh::Mesh load(const std::filesystem::path& path) {
    mesh::Mesh m;
    const Status loaded = mesh::load_mesh(path, m);
    REQUIRE_MESSAGE(loaded.is_ok(), loaded.message());
    return m;
}

double largest_distance(const mesh::Mesh& a, const mesh::Mesh& b) {
    REQUIRE(a.vertex_count() == b.vertex_count());
    double worst = 0.0;
    for (std::size_t v = 0; v < a.vertex_count(); ++v) {
        worst = std::max(worst, glm::length(a.positions[v] - b.positions[v]));
    }
    return worst;
}

}  // namespace

// The sample's arm is skinned by the host (the sample's own linear blend
// skinning, not Dualform's), its corrective edited in Dualform at a 120
// degree bend and driven by the elbow's angle. Read back from the meshes it
// writes: played at the edited bend, the corrected copy is the edit as
// Dualform showed it (the exact bind-space corrective, within 1e-5 of the
// diagonal after float storage); straight, the two copies are the same to
// the bit (the driver lets nothing through); half way, the corrective is
// partly on. The playback and the picture ran with the validation layer on
// (the sample fails on any message).
TEST_CASE("corrective: a corrective edited in a pose plays back exactly there and is off at rest") {
    const std::filesystem::path dir = test::scratch_dir("corrective");
    const std::string png = (dir / "corrective.png").string();
    const json::JsonValue report =
        run_corrective({"--frames", "120", "--png", png, "--meshes", dir.string()});
    CHECK(number_at(report, "frames") == 120);
    CHECK(number_at(report, "corrective", "vertices") > 100);
    CHECK(number_at(report, "corrective", "damped") == 0);
    CHECK(number_at(report, "gap", "straight") == 0);
    CHECK(number_at(report, "edited_pose_error") <= 1e-5);
    // The posed displacement copied into bind space as it is misses by far.
    CHECK(number_at(report, "naive_error") > 0.01);

    const mesh::Mesh edited = load(dir / "edited-120.off");
    const double diagonal = mesh::compute_bounds(edited.positions).diagonal();
    const double at_edit = largest_distance(load(dir / "corrected-120.off"), edited) / diagonal;
    MESSAGE("corrected copy at the edited bend vs the edit: " << at_edit << " of the diagonal");
    CHECK(at_edit <= 1e-5);
    const mesh::Mesh plain_straight = load(dir / "plain-0.off");
    const mesh::Mesh corrected_straight = load(dir / "corrected-0.off");
    REQUIRE(plain_straight.vertex_count() == corrected_straight.vertex_count());
    CHECK(plain_straight.positions == corrected_straight.positions);
    // Bent, the corrective shows: the copies part by a visible fraction of the
    // diagonal, less half way than at the edited bend.
    const double half =
        largest_distance(load(dir / "plain-60.off"), load(dir / "corrected-60.off"));
    const double bent =
        largest_distance(load(dir / "plain-120.off"), load(dir / "corrected-120.off"));
    MESSAGE("copies apart: " << half / diagonal << " half way, " << bent / diagonal << " bent");
    CHECK(bent > 0.02 * diagonal);
    CHECK(half > 0.0);
    CHECK(half < bent);

    // Three frames one above the other, each with both arms drawn.
    png_image image = {};
    image.version = PNG_IMAGE_VERSION;
    REQUIRE_MESSAGE(png_image_begin_read_from_file(&image, png.c_str()) != 0, png);
    image.format = PNG_FORMAT_RGBA;
    std::vector<std::uint8_t> rgba(PNG_IMAGE_SIZE(image));
    REQUIRE(png_image_finish_read(&image, nullptr, rgba.data(), 0, nullptr) != 0);
    CHECK(image.width == 960);
    REQUIRE(image.height == 840);
    for (std::uint32_t row = 0; row < 3; ++row) {
        std::size_t left = 0, right = 0;  // lit surface pixels of each half
        for (std::uint32_t y = row * 280; y < (row + 1) * 280; ++y) {
            for (std::uint32_t x = 0; x < image.width; ++x) {
                if (rgba[(std::size_t{y} * image.width + x) * 4 + 1] > 120) {
                    ++(x < image.width / 2 ? left : right);
                }
            }
        }
        CAPTURE(row);
        CHECK(left > 5000);
        CHECK(right > 5000);
    }
}

// The same playback in a GLFW window (Xvfb, lavapipe presenting), for a
// fixed number of frames.
TEST_CASE("corrective: plays in a window") {
    const json::JsonValue report = run_corrective({"--window", "--frames", "30"}, true);
    CHECK(number_at(report, "frames") == 30);
    CHECK(number_at(report, "gap", "straight") == 0);
}
