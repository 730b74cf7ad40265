#include <doctest/doctest.h>

#include <algorithm>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "environment/host_environment.hpp"
#include "mesh/gltf_io.hpp"
#include "mesh/host_mesh.hpp"
#include "mesh/load.hpp"
#include "mesh/model_cache.hpp"
#include "pick/pick.hpp"
#include "support/gltf_builder.hpp"
#include "support/model_variants.hpp"
#include "support/procedural_meshes.hpp"
#include "support/run_process.hpp"
#include "support/test_files.hpp"

using dfm::test::run_process;

namespace {

dfm::test::ProcessResult dualform(std::vector<std::string> args) {
    return run_process(DUALFORM_CLI, args);
}

// The text of a number or boolean field (its first occurrence) in the
// CLI's one-line JSON.
std::string field(const std::string& json, const std::string& key) {
    const std::string k = "\"" + key + "\":";
    const std::size_t at = json.find(k);
    if (at == std::string::npos) return "<missing>";
    const std::size_t start = at + k.size();
    return json.substr(start, json.find_first_of(",}", start) - start);
}

void check_info(const std::string& spec, const char* vertices, const char* faces) {
    CAPTURE(spec);
    const auto r = dualform({"info", spec});
    CAPTURE(r.err);
    REQUIRE(r.exit_code == 0);
    CHECK(r.out.front() == '{');
    CHECK(r.out.back() == '\n');
    CHECK(r.out.find('\n') == r.out.size() - 1);
    CHECK(field(r.out, "vertices") == vertices);
    CHECK(field(r.out, "faces") == faces);
    CHECK(field(r.out, "boundary_edges") == "0");
    CHECK(field(r.out, "non_manifold_edges") == "0");
    CHECK(field(r.out, "components") == "1");
    CHECK(field(r.out, "closed") == "true");
    CHECK(field(r.out, "degenerate_faces") == "0");
    CHECK(field(r.out, "bbox_diagonal") != "<missing>");
}

}  // namespace

TEST_CASE("dualform info: the real models") {
    check_info("model:cow", "2904", "5804");
    check_info("model:dino", "3916", "7828");
    check_info("model:armadillo", "26002", "52000");
    const auto r = dualform({"info", "model:cow"});
    CHECK(field(r.out, "bbox_diagonal").starts_with("1.2170"));
}

TEST_CASE("dualform info: the cow written as OBJ and PLY variants") {
    dfm::mesh::Mesh cow;
    std::filesystem::path path;
    REQUIRE(dfm::mesh::resolve_mesh_spec("model:cow", {},
                                         dfm::tools::models_folder_from_environment(), path)
                .is_ok());
    REQUIRE(dfm::mesh::load_mesh(path, cow).is_ok());
    const auto dir = dfm::test::scratch_dir("cli_cow_variants");
    for (const auto& f : dfm::test::write_model_variants(cow, dir)) {
        check_info(f.string(), "2904", "5804");
    }
}

TEST_CASE("dualform convert: writes what info reads back") {
    const auto dir = dfm::test::scratch_dir("cli_convert");
    for (const char* name : {"cow.off", "cow.obj", "cow.ply"}) {
        const std::string out = (dir / name).string();
        const auto c = dualform({"convert", "model:cow", out, "--ply", "binary_big_endian"});
        CAPTURE(c.err);
        REQUIRE(c.exit_code == 0);
        check_info(out, "2904", "5804");
    }
}

TEST_CASE("dualform: bad input prints one error line and exits 2") {
    const auto dir = dfm::test::scratch_dir("cli_errors");
    dfm::test::write_text(dir / "bad.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 9\n");
    struct Case {
        std::vector<std::string> args;
        std::string message;
    };
    const std::string bad = (dir / "bad.off").string();
    const Case cases[] = {
        {{"info", (dir / "missing.off").string()}, "missing.off: no such file"},
        {{"info", dir.string()}, "is a directory"},
        {{"info", bad}, bad + ":6: face 0: vertex index 9 is out of range"},
        {{"info", "model:no-such-model"}, "run tools/fetch-models"},
        {{"info", "model:../etc"}, "a model name is a plain file name"},
        {{"info"}, "usage: dualform info"},
        {{"frobnicate"}, "unknown command 'frobnicate'"},
        {{"convert", "model:cow", (dir / "x.stl").string()}, "unknown mesh format"},
        {{"convert", "model:cow", (dir / "x.ply").string(), "--ply", "middle"}, "unknown encoding"},
    };
    for (const Case& c : cases) {
        CAPTURE(c.args[0]);
        CAPTURE(c.message);
        const auto r = dualform(c.args);
        CAPTURE(r.err);
        CHECK(r.exit_code == 2);
        CHECK(r.out.empty());
        CHECK(r.err.rfind("error: ", 0) == 0);
        CHECK(r.err.find(c.message) != std::string::npos);
    }
}

TEST_CASE("dualform: every malformed corpus file is a clean exit 2") {
    for (const auto& entry :
         std::filesystem::directory_iterator(dfm::test::data_dir() / "malformed")) {
        if (entry.path().filename() == "EXPECTED.tsv") continue;
        CAPTURE(entry.path().string());
        const auto r = dualform({"info", entry.path().string()});
        CHECK(r.exit_code == 2);
        // The C API's message: the call, then the file, line and element.
        CHECK(r.err.rfind("error: dfm_mesh_load_with_report: " + entry.path().string(), 0) == 0);
    }
}

TEST_CASE("dualform help exits 0 and lists the commands, their options and glTF") {
    const auto r = dualform({"help"});
    CHECK(r.exit_code == 0);
    CHECK(r.out.find("info PATH|model:NAME") != std::string::npos);
    for (const char* word : {"glTF", ".glb", "#mesh=NAME", "--morph-target NAME", "--roi-out",
                             "--hard-handles", "--method", "--ply-float", "--obj-normals",
                             "--preconditioner", "--workers", "--before-after", "--samples"}) {
        CAPTURE(word);
        CHECK(r.out.find(word) != std::string::npos);
    }
}

TEST_CASE("dualform: every command answers --help with its usage and exit 0") {
    for (const char* command : {"info", "convert", "deform", "bench", "pick", "roi", "render"}) {
        CAPTURE(command);
        for (const char* flag : {"--help", "-h"}) {
            const auto r = dualform({command, flag});
            CHECK(r.exit_code == 0);
            CHECK(r.err.empty());
            CHECK(r.out.rfind(std::string("usage: dualform ") + command + " ", 0) == 0);
        }
    }
    const auto deform = dualform({"deform", "--help"});
    CHECK(deform.out.find("--morph-target NAME") != std::string::npos);
    // After other arguments too, and a bad argument still exits 2.
    CHECK(dualform({"deform", "cow.json", "--help"}).exit_code == 0);
    const auto bad = dualform({"deform", "--frobnicate"});
    CHECK(bad.exit_code == 2);
    CHECK(bad.err.find("usage: dualform deform SCENARIO") != std::string::npos);
}

namespace {

std::filesystem::path scenarios_dir() {
    return dfm::test::data_dir().parent_path() / "scenarios";
}

}  // namespace

TEST_CASE("dualform deform: writes the mesh, the ROI and a report with every field") {
    const auto dir = dfm::test::scratch_dir("cli_deform");
    const std::string out = (dir / "cow.ply").string();
    const std::string report = (dir / "report.json").string();
    const std::string roi = (dir / "roi.txt").string();
    const auto r = dualform({"deform", (scenarios_dir() / "scale-cow-leg.json").string(), "--out",
                             out, "--report", report, "--roi-out", roi, "--strict"});
    CAPTURE(r.err);
    REQUIRE(r.exit_code == 0);
    const std::string json = dfm::test::read_text(report);
    CHECK(json == r.out);
    for (const char* key :
         {"mesh", "n_vertices", "n_faces", "n_roi", "n_handles", "iterations", "converged",
          "setup_ms", "solve_ms", "ms_per_iteration", "krylov_iterations", "max_handle_error",
          "mean_abs_log_edge", "max_abs_log_edge", "mean_normal_change_deg", "max_fixed_move",
          "dual_magnitude_error", "flipped_faces", "creased_edges"}) {
        CAPTURE(key);
        CHECK(field(json, key) != "<missing>");
    }
    CHECK(field(json, "n_vertices") == "2904");
    CHECK(field(json, "converged") == "true");
    CHECK(field(json, "max_fixed_move") == "0");
    check_info(out, "2904", "5804");

    std::istringstream lines(dfm::test::read_text(roi));
    std::vector<long> indices;
    for (std::string line; std::getline(lines, line);) indices.push_back(std::stol(line));
    CHECK(std::to_string(indices.size()) == field(json, "n_roi"));
    CHECK(std::is_sorted(indices.begin(), indices.end()));
    CHECK(std::adjacent_find(indices.begin(), indices.end()) == indices.end());
}

TEST_CASE("dualform deform: a Water-Filling ROI deforms, bad input exits 2") {
    const auto dir = dfm::test::scratch_dir("cli_deform_errors");
    const std::string out = (dir / "x.off").string();
    auto r = dualform({"deform", (scenarios_dir() / "cow-front-leg-step.json").string(), "--out",
                       (dir / "leg.off").string()});
    CAPTURE(r.err);
    CHECK(r.exit_code == 0);
    CHECK(field(r.out, "n_roi") == "138");

    dfm::test::write_text(dir / "outside.json",
                          R"({"mesh": "model:cow", "roi": {"ball": {"center": 901, "radius": 0.1}},
                              "handles": [{"vertices": [0], "translate": [0.1, 0, 0]}]})");
    r = dualform({"deform", (dir / "outside.json").string(), "--out", out});
    CHECK(r.exit_code == 2);
    CHECK(r.err.find("handles[0]: vertex 0 is outside the ROI") != std::string::npos);

    dfm::test::write_text(dir / "typo.json",
                          R"({"mesh": "model:cow", "roi": {"all": true}, "handels": []})");
    r = dualform({"deform", (dir / "typo.json").string(), "--out", out});
    CHECK(r.exit_code == 2);
    CHECK(r.err.find("handels") != std::string::npos);
    CHECK_FALSE(std::filesystem::exists(out));

    r = dualform({"deform", (scenarios_dir() / "scale-cow-leg.json").string()});
    CHECK(r.exit_code == 2);
}

TEST_CASE("dualform deform --strict: a capped, unconverged solve exits 1") {
    const auto dir = dfm::test::scratch_dir("cli_deform_strict");
    dfm::test::write_text(dir / "capped.json",
                          R"({"mesh": "model:cow", "roi": {"ball": {"center": 901, "radius": 0.2}},
                              "handles": [{"ball": {"center": 901, "radius": 0.04}, "translate": [0.1, 0, 0]}],
                              "solver": {"max_iterations": 1, "tolerance": 1e-9}})");
    const auto r = dualform(
        {"deform", (dir / "capped.json").string(), "--out", (dir / "x.off").string(), "--strict"});
    CHECK(r.exit_code == 1);
    CHECK(field(r.out, "converged") == "false");
    CHECK(r.err.find("did not converge") != std::string::npos);
}

TEST_CASE("dualform: an output it cannot write exits 1, a malformed scenario 2") {
    const auto dir = dfm::test::scratch_dir("cli_exit_codes");
    const std::string scenario = (scenarios_dir() / "scale-cow-leg.json").string();
    const std::filesystem::path nowhere = dir / "no-such-folder";
    struct Case {
        std::vector<std::string> args;
        std::string message;
    };
    const Case unwritable[] = {
        {{"deform", scenario, "--out", (nowhere / "x.off").string()}, "no-such-folder"},
        {{"deform", scenario, "--out", (dir / "x.off").string(), "--report",
          (nowhere / "r.json").string()},
         "r.json: cannot write"},
        {{"deform", scenario, "--out", (dir / "x.off").string(), "--roi-out",
          (nowhere / "roi.txt").string()},
         "roi.txt: cannot write"},
        {{"roi", scenario, "--out", (nowhere / "roi.txt").string()}, "roi.txt: cannot write"},
        {{"convert", "model:cow", (nowhere / "cow.obj").string()}, "no-such-folder"},
        {{"bench", scenario, "--repeat", "1", "--json", (nowhere / "b.json").string()},
         "b.json: cannot write"},
    };
    for (const Case& c : unwritable) {
        CAPTURE(c.args[0]);
        const auto r = dualform(c.args);
        CAPTURE(r.err);
        CHECK(r.exit_code == 1);
        // The error ends stderr (bench prints its progress before it).
        const std::size_t error = r.err.rfind("error: ");
        REQUIRE(error != std::string::npos);
        CHECK(r.err.find(c.message, error) != std::string::npos);
        CHECK(r.err.find('\n', error) == r.err.size() - 1);
    }
    CHECK_FALSE(std::filesystem::exists(nowhere));

    dfm::test::write_text(dir / "malformed.json", R"({"mesh": "model:cow", "roi": )");
    const std::string malformed = (dir / "malformed.json").string();
    const std::vector<std::string> malformed_runs[] = {
        {"deform", malformed, "--out", (dir / "y.off").string()},
        {"roi", malformed, "--out", (dir / "y.txt").string()},
        {"bench", malformed},
    };
    for (const std::vector<std::string>& args : malformed_runs) {
        CAPTURE(args[0]);
        const auto r = dualform(args);
        CHECK(r.exit_code == 2);
        CHECK(r.err.find("malformed.json:1:") != std::string::npos);
    }
    // An output format the library does not write is a bad argument, not failed work.
    CHECK(dualform({"deform", scenario, "--out", (dir / "x.stl").string()}).exit_code == 2);
}

TEST_CASE("dualform bench: set-up, solve and a 60-frame drag, as JSON") {
    const auto dir = dfm::test::scratch_dir("cli_bench");
    const std::string json_path = (dir / "bench.json").string();
    const auto r = dualform({"bench", (scenarios_dir() / "scale-cow-leg.json").string(), "--repeat",
                             "2", "--json", json_path});
    CAPTURE(r.err);
    REQUIRE(r.exit_code == 0);
    const std::string json = dfm::test::read_text(json_path);
    for (const char* key :
         {"setup_ms", "solve_ms", "median", "p90", "p99", "drag", "frame_ms",
          "iterations_per_frame", "peak_rss_mib", "quality", "memory_mib", "factor",
          "normal_matrix", "iteration", "frame_slots", "staging", "session", "mesh_model"}) {
        CAPTURE(key);
        REQUIRE(json.find(std::string("\"") + key + "\"") != std::string::npos);
    }
    // The session is the sum of its parts, each held, and lies within the
    // process's peak beside the mesh.
    const auto mib = [&](const char* key) { return std::stod(field(json, key)); };
    const double parts = mib("factor") + mib("normal_matrix") + mib("iteration") +
                         mib("frame_slots") + mib("staging");
    CHECK(mib("session") == doctest::Approx(parts).epsilon(1e-9));
    for (const char* key : {"factor", "normal_matrix", "iteration", "frame_slots", "mesh_model"}) {
        CAPTURE(key);
        CHECK(mib(key) > 0.0);
    }
    CHECK(mib("session") + mib("mesh_model") < mib("peak_rss_mib"));
    CHECK(field(json, "frames") == "60");
    CHECK(field(json, "unconverged_frames") == "0");
    CHECK(field(json, "most_flipped_faces") == "0");
    CHECK(field(json, "most_creased_edges") == "0");
    CHECK(dualform({"bench", "--repeat", "0", "x.json"}).exit_code == 2);
}

namespace {

const char* cow_camera =
    R"({"eye": [0.2, 0.1, 2.0], "target": [0, 0, 0], "up": [0, 1, 0], "fov_y_degrees": 40,
        "width": 640, "height": 480})";

std::vector<long> read_roi(const std::filesystem::path& path) {
    std::istringstream lines(dfm::test::read_text(path));
    std::vector<long> indices;
    for (std::string line; std::getline(lines, line);) indices.push_back(std::stol(line));
    return indices;
}

}  // namespace

TEST_CASE("dualform pick: a hit prints face, vertex, point, distance and barycentrics") {
    auto r = dualform({"pick", "model:cow", "--camera", cow_camera, "--pixel", "320,240"});
    CAPTURE(r.err);
    REQUIRE(r.exit_code == 0);
    CHECK(r.out.starts_with("{\"hit\":true,\"face\":"));
    CHECK(r.out.find('\n') == r.out.size() - 1);
    for (const char* key : {"face", "vertex", "point", "distance", "barycentric"}) {
        CAPTURE(key);
        CHECK(field(r.out, key) != "<missing>");
    }
    // The same camera from a file gives the same answer.
    const auto dir = dfm::test::scratch_dir("cli_pick");
    dfm::test::write_text(dir / "camera.json", cow_camera);
    const auto f = dualform(
        {"pick", "model:cow", "--camera", (dir / "camera.json").string(), "--pixel", "320,240"});
    CHECK(f.exit_code == 0);
    CHECK(f.out == r.out);

    r = dualform({"pick", "model:cow", "--camera", cow_camera, "--pixel", "0,0"});
    CHECK(r.exit_code == 0);
    CHECK(r.out == "{\"hit\":false}\n");
}

TEST_CASE("dualform pick: bad input exits 2 and names it") {
    auto r = dualform({"pick", "model:cow", "--camera", cow_camera, "--pixel", "320"});
    CHECK(r.exit_code == 2);
    CHECK(r.err.find("--pixel") != std::string::npos);
    r = dualform({"pick", "model:cow", "--camera", cow_camera, "--pixel", "700,10"});
    CHECK(r.exit_code == 2);
    CHECK(r.err.find("outside") != std::string::npos);
    r = dualform({"pick", "model:cow", "--camera", R"({"eye": [0, 0, 1]})", "--pixel", "1,1"});
    CHECK(r.exit_code == 2);
    CHECK(r.err.find("target: required field is missing") != std::string::npos);
    r = dualform({"pick", "model:cow", "--camera", "/nonexistent/camera.json", "--pixel", "1,1"});
    CHECK(r.exit_code == 2);
    CHECK(r.err.find("cannot open") != std::string::npos);
    r = dualform({"pick", "model:cow", "--pixel", "1,1"});
    CHECK(r.exit_code == 2);
    CHECK(r.err.find("usage") != std::string::npos);
}

TEST_CASE("dualform roi: writes the Water-Filling ROI and its diagnosis") {
    const auto dir = dfm::test::scratch_dir("cli_roi");
    auto r = dualform({"roi", (scenarios_dir() / "cow-front-leg-step.json").string(), "--out",
                       (dir / "leg.txt").string()});
    CAPTURE(r.err);
    REQUIRE(r.exit_code == 0);
    CHECK(r.out == "{\"n_roi\":138,\"loops\":1,\"bounded_by_last_loop\":true,\"suspect\":false}\n");
    const std::vector<long> leg = read_roi(dir / "leg.txt");
    CHECK(leg.size() == 138);
    CHECK(std::is_sorted(leg.begin(), leg.end()));
    CHECK(std::adjacent_find(leg.begin(), leg.end()) == leg.end());

    dfm::test::write_text(
        dir / "tail.json",
        R"({"mesh": "model:cow", "roi": {"water_fill": {"first": 2334, "last": 1959}},
                              "handles": [{"vertices": [2334]}]})");
    r = dualform({"roi", (dir / "tail.json").string(), "--out", (dir / "tail.txt").string()});
    CHECK(r.exit_code == 0);
    CHECK(field(r.out, "loops") == "2");
    CHECK(field(r.out, "suspect") == "true");

    r = dualform({"roi", (scenarios_dir() / "scale-cow-leg.json").string(), "--out",
                  (dir / "ball.txt").string()});
    CHECK(r.exit_code == 0);
    CHECK(field(r.out, "loops") == "<missing>");
    CHECK(field(r.out, "n_roi") == std::to_string(read_roi(dir / "ball.txt").size()));

    dfm::test::write_text(
        dir / "far.json",
        R"({"mesh": "model:cow", "roi": {"water_fill": {"first": 771, "last": 9999}},
                              "handles": [{"vertices": [771]}]})");
    r = dualform({"roi", (dir / "far.json").string(), "--out", (dir / "far.txt").string()});
    CHECK(r.exit_code == 2);
    CHECK(r.err.find("last vertex 9999 is out of range") != std::string::npos);
    CHECK(dualform({"roi", (dir / "far.json").string()}).exit_code == 2);
}

// The clicks are the pixels where a camera sees vertices 771 and 681;
// picking them must give the same ROI as water_fill with 771 and 681.
TEST_CASE("dualform roi: water_fill_clicks replays the water_fill ROI") {
    dfm::mesh::Mesh cow;
    std::filesystem::path path;
    REQUIRE(dfm::mesh::resolve_mesh_spec("model:cow", {},
                                         dfm::tools::models_folder_from_environment(), path)
                .is_ok());
    REQUIRE(dfm::mesh::load_mesh(path, cow).is_ok());
    // A camera in front of the leg and below the hoof (771 is on the hoof's
    // sole), from where both vertices are seen: picking their projections
    // gives them back.
    dfm::pick::EmbreeScene scene;
    REQUIRE(dfm::pick::EmbreeScene::create(cow.positions, cow.triangles, scene).is_ok());
    dfm::pick::Camera camera;
    camera.target = 0.5 * (cow.positions[771] + cow.positions[681]);
    camera.eye = camera.target + glm::dvec3(0.5, -0.3, 0.0);
    camera.up = glm::dvec3(0.0, 1.0, 0.0);
    camera.fov_y_degrees = 40.0;
    camera.width = 640;
    camera.height = 480;
    for (const std::uint32_t v : {771u, 681u}) {
        const auto at = dfm::pick::project(camera, cow.positions[v]);
        REQUIRE(at.has_value());
        std::optional<dfm::pick::Hit> hit;
        REQUIRE(dfm::pick::pick_pixel(scene, camera, *at, hit).is_ok());
        REQUIRE(hit.has_value());
        CHECK(hit->vertex == v);
    }
    const auto first = dfm::pick::project(camera, cow.positions[771]);
    const auto last = dfm::pick::project(camera, cow.positions[681]);
    const auto number = [](double v) {
        std::ostringstream s;
        s.precision(17);
        s << v;
        return s.str();
    };
    const auto vec = [&](glm::dvec3 v) {
        std::string out = "[";
        out += number(v.x);
        out += ", ";
        out += number(v.y);
        out += ", ";
        out += number(v.z);
        out += ']';
        return out;
    };
    const auto pixel = [&](glm::dvec2 p) {
        std::string out = "[";
        out += number(p.x);
        out += ", ";
        out += number(p.y);
        out += ']';
        return out;
    };
    std::string camera_json = "{\"eye\": ";
    camera_json += vec(camera.eye);
    camera_json += ", \"target\": ";
    camera_json += vec(camera.target);
    camera_json += ", \"up\": [0, 1, 0], \"fov_y_degrees\": 40, \"width\": 640, \"height\": 480}";
    std::string scenario =
        R"({"mesh": "model:cow", "handles": [{"vertices": [771]}], "roi": {"water_fill_clicks": {"camera": )";
    scenario += camera_json;
    scenario += ", \"first\": ";
    scenario += pixel(*first);
    scenario += ", \"last\": ";
    scenario += pixel(*last);
    scenario += "}}}";

    const auto dir = dfm::test::scratch_dir("cli_roi_clicks");
    dfm::test::write_text(dir / "clicks.json", scenario);
    auto r =
        dualform({"roi", (dir / "clicks.json").string(), "--out", (dir / "clicks.txt").string()});
    CAPTURE(r.err);
    REQUIRE(r.exit_code == 0);
    const auto p = dualform({"roi", (scenarios_dir() / "cow-front-leg-step.json").string(), "--out",
                             (dir / "ids.txt").string()});
    REQUIRE(p.exit_code == 0);
    CHECK(r.out == p.out);
    CHECK(read_roi(dir / "clicks.txt") == read_roi(dir / "ids.txt"));

    // A camera looking away from the cow: the first click hits nothing.
    dfm::test::write_text(dir / "miss.json",
                          R"({"mesh": "model:cow", "handles": [{"vertices": [771]}],
                              "roi": {"water_fill_clicks": {"camera": {"eye": [0, 0, 3],
                              "target": [0, 0, 4], "up": [0, 1, 0], "fov_y_degrees": 40,
                              "width": 64, "height": 48}, "first": [32, 24], "last": [1, 1]}}})");
    r = dualform({"roi", (dir / "miss.json").string(), "--out", (dir / "miss.txt").string()});
    CHECK(r.exit_code == 2);
    CHECK(r.err.find("roi.water_fill_clicks.first: the click at [32, 24] hits nothing") !=
          std::string::npos);
}

TEST_CASE("dualform deform: a glTF mesh by #mesh=, written back and as a morph target") {
    const auto dir = dfm::test::scratch_dir("cli_gltf");
    const dfm::mesh::Mesh limb = dfm::test::split_corners(dfm::test::make_limb(12, 8, 0.2, 2.0),
                                                          [](std::size_t t) { return t % 2 == 0; });
    dfm::test::GltfBuilder b;
    b.positions(dfm::test::float_positions(limb));
    std::vector<std::uint32_t> idx;
    for (const auto& t : limb.triangles) idx.insert(idx.end(), t.begin(), t.end());
    b.indices_u32(idx);
    b.positions({0, 0, 0, 1, 0, 0, 0, 1, 0});
    b.members =
        R"("meshes":[{"name":"limb","primitives":[{"attributes":{"POSITION":0},"indices":1}]},)"
        R"({"name":"sail","primitives":[{"attributes":{"POSITION":2}}]}],)"
        R"("scenes":[{"nodes":[0,1]}],"nodes":[{"mesh":0},{"mesh":1}])";
    dfm::test::write_text(dir / "limb.glb", b.glb());
    // The tip's centre by its last copy: any copy names the surface vertex.
    std::uint32_t tip = 0;
    for (std::uint32_t v = 0; v < limb.vertex_count(); ++v) {
        if (limb.positions[v] == glm::dvec3(0, 2, 0)) tip = v;
    }
    REQUIRE(tip >= dfm::test::make_limb(12, 8, 0.2, 2.0).vertex_count());
    dfm::test::write_text(dir / "bend.json",
                          R"({"mesh": ")" + (dir / "limb.glb").string() +
                              R"(#mesh=limb", "roi": {"ball": {"center": )" + std::to_string(tip) +
                              R"(, "radius": 0.5}}, "handles": [{"vertices": [)" +
                              std::to_string(tip) + R"(], "translate": [0.1, 0, 0]}]})");
    auto r =
        dualform({"deform", (dir / "bend.json").string(), "--out", (dir / "bent.glb").string()});
    CAPTURE(r.err);
    REQUIRE(r.exit_code == 0);
    CHECK(field(r.out, "n_vertices") == std::to_string(limb.vertex_count()));
    dfm::mesh::Mesh bent;
    dfm::mesh::HostMesh host;
    REQUIRE(dfm::mesh::load_host_mesh(dir / "bent.glb", bent, host));
    CHECK(host.weld->host_vertex_count() == limb.vertex_count() + 3);  // the sail too
    // No crack: every copy of the tip's centre lands where the tip went.
    std::string written;
    REQUIRE(dfm::mesh::read_file_bytes(dir / "bent.glb", written));
    dfm::mesh::Mesh raw;
    dfm::mesh::GltfAsset asset;
    dfm::mesh::LoadReport loaded;
    dfm::mesh::Skin skin;
    REQUIRE(dfm::mesh::read_gltf(written, "bent.glb", nullptr, "limb", raw, asset, skin, loaded));
    CHECK(raw.positions[tip].x > 0.1);
    for (std::uint32_t v = 0; v < limb.vertex_count(); ++v) {
        if (limb.positions[v] == limb.positions[tip]) CHECK(raw.positions[v] == raw.positions[tip]);
    }

    r = dualform({"deform", (dir / "bend.json").string(), "--out", (dir / "morph.glb").string(),
                  "--morph-target", "bend"});
    REQUIRE(r.exit_code == 0);
    std::string bytes;
    REQUIRE(dfm::mesh::read_file_bytes(dir / "morph.glb", bytes));
    CHECK(bytes.find(R"("targetNames":["bend"])") != std::string::npos);
    CHECK(bytes.find(R"("targets":[{"POSITION")") != std::string::npos);

    r = dualform({"info", (dir / "limb.glb").string() + "#mesh=limb"});
    REQUIRE(r.exit_code == 0);
    CHECK(field(r.out, "vertices") == std::to_string(limb.vertex_count()));
    CHECK(field(r.out, "surface_vertices") ==
          std::to_string(dfm::test::make_limb(12, 8, 0.2, 2.0).vertex_count()));
    CHECK(field(r.out, "closed") == "true");

    r = dualform({"deform", (dir / "bend.json").string(), "--out", (dir / "x.off").string(),
                  "--morph-target", "bend"});
    CHECK(r.exit_code == 2);
    CHECK(r.err.find("a morph target is written only to .gltf or .glb") != std::string::npos);
}

TEST_CASE("dualform deform: a glTF asset cannot pull a file outside its folder into the output") {
    dfm::test::GltfBuilder b;
    b.positions({0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1});
    b.indices_u16({0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3});
    b.members = R"("meshes":[{"primitives":[{"attributes":{"POSITION":0},"indices":1}]}])";
    const auto dir = dfm::test::scratch_dir("cli_gltf_references");
    std::filesystem::create_directories(dir / "asset");
    // The "secret" is a valid buffer of the right length, so that only the
    // rule stops it.
    dfm::test::write_text(dir / "secret.bin", b.bin());
    dfm::test::write_text(dir / "asset" / "tet.gltf", b.json("../secret.bin"));
    dfm::test::write_text(dir / "asset" / "edit.json",
                          R"({"mesh": "tet.gltf", "roi": {"all": true},
                              "handles": [{"vertices": [3], "translate": [0, 0, 0.1]}]})");
    const std::filesystem::path out = dir / "out.gltf";
    const auto r =
        dualform({"deform", (dir / "asset" / "edit.json").string(), "--out", out.string()});
    CHECK(r.exit_code == 2);
    CHECK(r.err.find("external file URI '../secret.bin' refused") != std::string::npos);
    CHECK_FALSE(std::filesystem::exists(out));
}
