#include <doctest/doctest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <string>
#include <string_view>

#include "dualform/scenario.hpp"
#include "support/test_files.hpp"

using namespace dfm::cli;

namespace {

std::filesystem::path scenarios_dir() {
    return dfm::test::data_dir().parent_path() / "scenarios";
}

Scenario parse_ok(std::string_view text) {
    Scenario out;
    const dfm::ToolStatus s = parse_scenario(text, "s.json", out);
    INFO(s.message());
    REQUIRE(s.is_ok());
    return out;
}

// "s.json:LINE:COL: " for the first occurrence of `marker` in `text`.
std::string location_of(std::string_view text, std::string_view marker) {
    const std::size_t at = text.find(marker);
    REQUIRE(at != std::string_view::npos);
    const std::string_view before = text.substr(0, at);
    const std::size_t line =
        1 + static_cast<std::size_t>(std::count(before.begin(), before.end(), '\n'));
    const std::size_t line_start =
        before.rfind('\n') == std::string_view::npos ? 0 : before.rfind('\n') + 1;
    std::string out = "s.json:";
    out += std::to_string(line);
    out += ':';
    out += std::to_string(at - line_start + 1);
    out += ": ";
    return out;
}

// `text` must fail with the message `located` and leave the output empty.
void check_message(std::string_view text, const std::string& located) {
    CAPTURE(text);
    Scenario out;
    out.mesh = "left over";
    out.handles.resize(2);
    const dfm::ToolStatus s = parse_scenario(text, "s.json", out);
    REQUIRE_FALSE(s.is_ok());
    CHECK(s.code() == DFM_ERROR_PARSE);
    CHECK(s.message() == located);
    CHECK(out.mesh.empty());
    CHECK(out.handles.empty());
}

// The message must be the location of `marker`, then `rest`.
void check_error(std::string_view text, std::string_view marker, std::string_view rest) {
    check_message(text, location_of(text, marker) + std::string(rest));
}

// A scenario with the given roi, handles and further top-level members.
std::string with(std::string_view roi, std::string_view handles, std::string_view more = "") {
    std::string text = R"({"mesh": "m.off", "roi": )";
    text += roi;
    text += R"(, "handles": )";
    text += handles;
    text += more;
    text += '}';
    return text;
}

constexpr std::string_view any_roi = R"({"all": true})";
constexpr std::string_view any_handles = R"([{"vertices": [7]}])";

std::string with_roi(std::string_view roi) {
    return with(roi, any_handles);
}
std::string with_handle(std::string_view handle) {
    std::string handles = "[";
    handles += handle;
    handles += ']';
    return with(any_roi, handles);
}
std::string with_solver(std::string_view solver) {
    std::string more = R"(, "solver": )";
    more += solver;
    return with(any_roi, any_handles, more);
}

constexpr std::string_view camera_text =
    R"({"eye": [0, 0, 5], "target": [0, 0, 0], "up": [0, 1, 0], )"
    R"("fov_y_degrees": 45, "width": 640, "height": 480})";

// A water_fill_clicks ROI whose camera has `field` replaced by `value`.
std::string with_camera_field(std::string_view field, std::string_view value) {
    std::string camera(camera_text);
    std::string key = "\"";
    key += field;
    key += "\": ";
    REQUIRE(camera.find(key) != std::string::npos);
    const std::size_t start = camera.find(key) + key.size();
    const std::size_t end =
        camera.find_first_of(",}", camera[start] == '[' ? camera.find(']', start) : start);
    camera.replace(start, end - start, value);
    std::string roi = R"({"water_fill_clicks": {"camera": )";
    roi += camera;
    roi += R"(, "first": [320, 240], "last": [100, 50]}})";
    return with_roi(roi);
}

}  // namespace

TEST_CASE("scenario: the example scenarios parse") {
    const char* names[] = {"armadillo-ear-ball", "camel-head-turn", "cow-front-leg-step",
                           "cow-tail-swing",     "dino-tail-lift",  "triceratops-horn-rotate"};
    for (const char* name : names) {
        CAPTURE(name);
        const std::filesystem::path path = scenarios_dir() / (std::string(name) + ".json");
        Scenario s;
        const dfm::ToolStatus status = load_scenario(path, s);
        INFO(status.message());
        REQUIRE(status.is_ok());
        CHECK(s.mesh.starts_with("model:"));
        CHECK(s.base_dir == scenarios_dir());
        REQUIRE(s.handles.size() == 1);
        CHECK(s.handles[0].ball.has_value());
        CHECK(s.handles[0].vertices.empty());
        CHECK(s.handles[0].targets.empty());
    }

    Scenario camel;
    REQUIRE(load_scenario(scenarios_dir() / "camel-head-turn.json", camel).is_ok());
    CHECK(camel.mesh == "model:camel");
    CHECK(camel.roi.kind == RoiSpec::Kind::water_fill);
    CHECK(camel.roi.first == 315);
    CHECK(camel.roi.last == 1858);
    CHECK(camel.handles[0].ball->center == 315);
    CHECK(camel.handles[0].ball->radius == 0.03);
    CHECK(*camel.handles[0].translate == glm::dvec3(0.1, 0.0, -0.03));
    CHECK_FALSE(camel.handles[0].rotate.has_value());
    CHECK_FALSE(camel.solver.tolerance.has_value());
    CHECK_FALSE(camel.solver.max_iterations.has_value());
    CHECK_FALSE(camel.solver.handle_weight.has_value());

    Scenario armadillo;
    REQUIRE(load_scenario(scenarios_dir() / "armadillo-ear-ball.json", armadillo).is_ok());
    CHECK(armadillo.roi.kind == RoiSpec::Kind::ball);
    CHECK(armadillo.roi.ball.center == 4530);
    CHECK(armadillo.roi.ball.radius == 0.15);
    CHECK(*armadillo.solver.tolerance == 1e-5);
    CHECK(*armadillo.solver.max_iterations == 50);
    CHECK(*armadillo.solver.handle_weight == 1.0);

    Scenario triceratops;
    REQUIRE(load_scenario(scenarios_dir() / "triceratops-horn-rotate.json", triceratops).is_ok());
    const HandleSpec& horn = triceratops.handles[0];
    CHECK_FALSE(horn.translate.has_value());
    REQUIRE(horn.rotate.has_value());
    CHECK(horn.rotate->axis == glm::dvec3(0.0, 0.0, 1.0));
    CHECK(horn.rotate->degrees == 25.0);
    CHECK_FALSE(horn.rotate->pivot_is_centroid);
    CHECK(horn.rotate->pivot == glm::dvec3(5.9665, 1.6318, 0.68));
}

TEST_CASE("scenario: the example of docs/scenarios.md") {
    const Scenario s = parse_ok(R"({
  "mesh": "model:camel",
  "roi": { "water_fill": { "first": 812, "last": 1033 } },
  "handles": [
    { "vertices": [17, 18, 19], "translate": [0.0, 0.1, 0.0] },
    { "ball": { "center": 640, "radius": 0.03 },
      "rotate": { "axis": [0, 0, 1], "degrees": 30, "pivot": "centroid" } }
  ],
  "solver": { "tolerance": 1e-5, "max_iterations": 50, "handle_weight": 1.0 }
})");
    CHECK(s.mesh == "model:camel");
    CHECK(s.base_dir.empty());
    CHECK(s.roi.kind == RoiSpec::Kind::water_fill);
    CHECK(s.roi.first == 812);
    CHECK(s.roi.last == 1033);
    REQUIRE(s.handles.size() == 2);
    CHECK(s.handles[0].vertices == std::vector<std::uint32_t>{17, 18, 19});
    CHECK_FALSE(s.handles[0].ball.has_value());
    CHECK(*s.handles[0].translate == glm::dvec3(0.0, 0.1, 0.0));
    CHECK(s.handles[1].vertices.empty());
    CHECK(s.handles[1].ball->center == 640);
    CHECK(s.handles[1].ball->radius == 0.03);
    CHECK_FALSE(s.handles[1].translate.has_value());
    CHECK(s.handles[1].rotate->axis == glm::dvec3(0.0, 0.0, 1.0));
    CHECK(s.handles[1].rotate->degrees == 30.0);
    CHECK(s.handles[1].rotate->pivot_is_centroid);
    CHECK(*s.solver.tolerance == 1e-5);
    CHECK(*s.solver.max_iterations == 50);
    CHECK(*s.solver.handle_weight == 1.0);
}

TEST_CASE("scenario: every ROI kind") {
    Scenario s = parse_ok(with_roi(R"({"vertices": [0, 4294967294, 5]})"));
    CHECK(s.roi.kind == RoiSpec::Kind::vertices);
    CHECK(s.roi.vertices == std::vector<std::uint32_t>{0, 4294967294u, 5});

    s = parse_ok(with_roi(R"({"all": true})"));
    CHECK(s.roi.kind == RoiSpec::Kind::all);

    s = parse_ok(with_roi(R"({"ball": {"radius": 0.25, "center": 9}})"));
    CHECK(s.roi.kind == RoiSpec::Kind::ball);
    CHECK(s.roi.ball.center == 9);
    CHECK(s.roi.ball.radius == 0.25);

    std::string clicks = R"({"water_fill_clicks": {"camera": )";
    clicks += camera_text;
    clicks += R"(, "first": [0, 0], "last": [640, 479.5]}})";
    s = parse_ok(with_roi(clicks));
    CHECK(s.roi.kind == RoiSpec::Kind::water_fill_clicks);
    const dfm_camera& c = s.roi.camera;
    CHECK(glm::dvec3(c.eye[0], c.eye[1], c.eye[2]) == glm::dvec3(0.0, 0.0, 5.0));
    CHECK(glm::dvec3(c.target[0], c.target[1], c.target[2]) == glm::dvec3(0.0));
    CHECK(glm::dvec3(c.up[0], c.up[1], c.up[2]) == glm::dvec3(0.0, 1.0, 0.0));
    CHECK(s.roi.camera.fov_y_degrees == 45.0);
    CHECK(s.roi.camera.width == 640);
    CHECK(s.roi.camera.height == 480);
    CHECK(s.roi.first_pixel == glm::dvec2(0.0, 0.0));
    CHECK(s.roi.last_pixel == glm::dvec2(640.0, 479.5));
}

TEST_CASE("scenario: handle groups: selections, motions and fixed anchors") {
    const Scenario s = parse_ok(with(any_roi, R"([
        {"vertices": [3, 1]},
        {"vertices": [4, 5], "targets": [[1, 2, 3], [-1, 0.5, 1e-3]]},
        {"ball": {"center": 2, "radius": 1}, "rotate": {"axis": [1, 0, 0], "degrees": -90}},
        {"vertices": [6], "translate": [1, 0, 0],
         "rotate": {"degrees": 45, "pivot": [1, 2, 3], "axis": [0, 2, 0]}}
    ])"));
    REQUIRE(s.handles.size() == 4);
    const HandleSpec& anchor = s.handles[0];
    CHECK(anchor.vertices == std::vector<std::uint32_t>{3, 1});
    CHECK_FALSE(anchor.translate.has_value());
    CHECK_FALSE(anchor.rotate.has_value());
    CHECK(anchor.targets.empty());
    CHECK(s.handles[1].targets ==
          std::vector<glm::dvec3>{glm::dvec3(1, 2, 3), glm::dvec3(-1, 0.5, 1e-3)});
    CHECK(s.handles[2].rotate->pivot_is_centroid);
    CHECK(s.handles[2].rotate->degrees == -90.0);
    CHECK(*s.handles[3].translate == glm::dvec3(1, 0, 0));
    CHECK_FALSE(s.handles[3].rotate->pivot_is_centroid);
    CHECK(s.handles[3].rotate->pivot == glm::dvec3(1, 2, 3));
    CHECK(s.handles[3].rotate->axis == glm::dvec3(0, 2, 0));
}

TEST_CASE("scenario: solver fields are each optional") {
    Scenario s = parse_ok(with_solver("{}"));
    CHECK_FALSE(s.solver.tolerance.has_value());
    CHECK_FALSE(s.solver.max_iterations.has_value());
    CHECK_FALSE(s.solver.handle_weight.has_value());
    s = parse_ok(with_solver(R"({"max_iterations": 2147483647})"));
    CHECK(*s.solver.max_iterations == 2147483647);
    CHECK_FALSE(s.solver.tolerance.has_value());
}

TEST_CASE("scenario: a top-level description or comment string is allowed") {
    const Scenario s =
        parse_ok(with(any_roi, any_handles, R"(, "description": "lifts the tail", "comment": "")"));
    CHECK(s.mesh == "m.off");
    const std::string bad = with(any_roi, any_handles, R"(, "comment": ["x"])");
    check_error(bad, R"(["x"])", "comment: expected a string, found an array of 1 value");
    const std::string nested = with_roi(R"({"all": true, "description": "d"})");
    check_error(nested, R"("description")",
                "roi.description: unknown field (expected water_fill, water_fill_clicks, ball, "
                "vertices or all)");
}

TEST_CASE("scenario: the top level and mesh") {
    check_error("[]", "[", "expected an object, found an empty array");
    check_error(R"({"roi": {"all": true}, "handles": [{"vertices": [1]}]})", "{",
                "mesh: required field is missing");
    check_error(R"({"mesh": "m.off", "handles": [{"vertices": [1]}]})", "{",
                "roi: required field is missing");
    check_error(R"({"mesh": "m.off", "roi": {"all": true}})", "{",
                "handles: required field is missing");
    const std::string unknown = with(any_roi, any_handles, R"(, "mesh_file": "x")");
    check_error(unknown, R"("mesh_file")",
                "mesh_file: unknown field (expected mesh, subdivide, pose, roi, handles, solver, "
                "description or comment)");
    check_error(R"({"mesh": 3, "roi": {"all": true}, "handles": [{"vertices": [1]}]})", "3",
                "mesh: expected a string (a mesh file path or model:NAME), found 3");
    check_error(R"({"mesh": "", "roi": {"all": true}, "handles": [{"vertices": [1]}]})", R"("")",
                "mesh: expected a mesh file path or model:NAME, found \"\"");
    check_error(R"({"mesh": "model:", "roi": {"all": true}, "handles": [{"vertices": [1]}]})",
                R"("model:")", "mesh: expected a model name after \"model:\"");
    check_error(R"({"mesh": "a\u0000b", "roi": {"all": true}, "handles": [{"vertices": [1]}]})",
                R"("a\u)", "mesh: a mesh path cannot contain a NUL character");
    for (const char* bad : {"4", "-1", "1.5", "\"2\""}) {
        const std::string text =
            with(any_roi, any_handles, std::string(R"(, "subdivide": )") + bad);
        const std::size_t column = text.find(R"("subdivide": )") + 14;
        check_message(text, "s.json:1:" + std::to_string(column) +
                                ": subdivide: expected an integer from 0 to 3, found " +
                                (bad[0] == '"' ? "a string" : bad));
    }
}

TEST_CASE("scenario: subdivide names Loop steps for scale scenarios") {
    Scenario out;
    REQUIRE(
        parse_scenario(with(any_roi, any_handles, R"(, "subdivide": 2)"), "s.json", out).is_ok());
    CHECK(out.subdivide == 2);
    REQUIRE(parse_scenario(with(any_roi, any_handles), "s.json", out).is_ok());
    CHECK(out.subdivide == 0);
}

TEST_CASE("scenario: ROI errors") {
    check_error(with_roi(R"("all")"), R"("all")", "roi: expected an object, found a string");
    check_error(with_roi("{}"), "{}",
                "roi: expected one ROI kind (water_fill, water_fill_clicks, ball, vertices or "
                "all), found none");
    check_error(with_roi(R"({"all": true, "ball": {"center": 1, "radius": 1}})"), R"("ball")",
                "roi.ball: only one ROI kind is allowed, and all is already given");
    check_error(with_roi(R"({"water_fill": {"first": 1, "last": 2}, "vertices": [1]})"),
                R"("vertices")",
                "roi.vertices: only one ROI kind is allowed, and water_fill is already given");
    check_error(with_roi(R"({"everything": true})"), R"("everything")",
                "roi.everything: unknown field (expected water_fill, water_fill_clicks, ball, "
                "vertices or all)");
    check_error(with_roi(R"({"all": false})"), "false", "roi.all: expected true, found false");
    check_error(with_roi(R"({"all": 1})"), "1}", "roi.all: expected true, found 1");

    check_error(with_roi(R"({"water_fill": {"first": 1}})"), R"({"first")",
                "roi.water_fill.last: required field is missing");
    check_error(with_roi(R"({"water_fill": [1, 2]})"), "[1, 2]",
                "roi.water_fill: expected an object, found an array of 2 values");
    check_error(with_roi(R"({"water_fill": {"first": 1, "lats": 2}})"), R"("lats")",
                "roi.water_fill.lats: unknown field (expected first or last)");
    check_error(with_roi(R"({"water_fill": {"first": 4, "last": 4}})"), "4}",
                "roi.water_fill.last: must differ from first");
    const std::string index_rule =
        "expected a vertex index (an integer from 0 to 4294967294), found ";
    check_error(with_roi(R"({"water_fill": {"first": -1, "last": 2}})"), "-1",
                "roi.water_fill.first: " + index_rule + "-1");
    check_error(with_roi(R"({"water_fill": {"first": 1.5, "last": 2}})"), "1.5",
                "roi.water_fill.first: " + index_rule + "1.5");
    check_error(with_roi(R"({"water_fill": {"first": 2.0, "last": 3}})"), "2.0",
                "roi.water_fill.first: " + index_rule + "2.0");
    check_error(with_roi(R"({"water_fill": {"first": 1e2, "last": 3}})"), "1e2",
                "roi.water_fill.first: " + index_rule + "100.0");
    check_error(with_roi(R"({"water_fill": {"first": 1, "last": 4294967295}})"), "4294967295",
                "roi.water_fill.last: " + index_rule + "4294967295");
    check_error(with_roi(R"({"water_fill": {"first": "3", "last": 2}})"), R"("3")",
                "roi.water_fill.first: " + index_rule + "a string");
    check_error(with_roi(R"({"water_fill": {"first": null, "last": 2}})"), "null",
                "roi.water_fill.first: " + index_rule + "null");

    check_error(with_roi(R"({"ball": {"center": 1, "radius": 0}})"), "0}",
                "roi.ball.radius: expected a number greater than 0, found 0");
    check_error(with_roi(R"({"ball": {"center": 1, "radius": -0.5}})"), "-0.5",
                "roi.ball.radius: expected a number greater than 0, found -0.5");
    check_error(with_roi(R"({"ball": {"radius": 0.5}})"), R"({"radius")",
                "roi.ball.center: required field is missing");
    check_error(with_roi(R"({"ball": {"center": 1, "radius": true}})"), "true",
                "roi.ball.radius: expected a number greater than 0, found true");

    check_error(with_roi(R"({"vertices": []})"), "[]",
                "roi.vertices: expected at least one vertex index, found an empty array");
    check_error(with_roi(R"({"vertices": {}})"), "{}",
                "roi.vertices: expected an array of vertex indices, found an object");
    check_error(with_roi(R"({"vertices": [1, 2, 3, 2]})"), "2]",
                "roi.vertices[3]: vertex 2 is listed twice (first at [1])");
    check_error(with_roi(R"({"vertices": [1, "x"]})"), R"("x")",
                "roi.vertices[1]: " + index_rule + "a string");
}

TEST_CASE("scenario: camera and click errors") {
    const std::string base = "roi.water_fill_clicks.camera.";
    const std::string vec3_rule = "expected an array of 3 numbers [x, y, z], found ";
    check_error(with_camera_field("eye", "[0, 0]"), "[0, 0]",
                base + "eye: " + vec3_rule + "an array of 2 values");
    check_error(with_camera_field("eye", "[0, 0, \"5\"]"), "\"5\"",
                base + "eye[2]: expected a number, found a string");
    check_error(with_camera_field("target", "[0, 0, 5]"), "[0, 0, 5], \"up\"",
                base + "target: must differ from eye");
    const std::string up_rule =
        "must be non-zero and not parallel to the view direction (target - eye)";
    check_error(with_camera_field("up", "[0, 0, -2]"), "[0, 0, -2]", base + "up: " + up_rule);
    check_error(with_camera_field("up", "[0, 0, 0]"), "[0, 0, 0], \"fov", base + "up: " + up_rule);
    const std::string fov_rule =
        "expected an angle in degrees between 0 and 180, both excluded, found ";
    check_error(with_camera_field("fov_y_degrees", "0"), "0, \"width\"",
                base + "fov_y_degrees: " + fov_rule + "0");
    check_error(with_camera_field("fov_y_degrees", "180"), "180",
                base + "fov_y_degrees: " + fov_rule + "180");
    check_error(with_camera_field("fov_y_degrees", "-5"), "-5",
                base + "fov_y_degrees: " + fov_rule + "-5");
    check_error(with_camera_field("fov_y_degrees", "\"wide\""), "\"wide\"",
                base + "fov_y_degrees: " + fov_rule + "a string");
    const std::string size_rule = "expected a positive integer (at most 4294967295), found ";
    check_error(with_camera_field("width", "0"), "0, \"height\"",
                base + "width: " + size_rule + "0");
    check_error(with_camera_field("width", "640.5"), "640.5",
                base + "width: " + size_rule + "640.5");
    check_error(with_camera_field("height", "4294967296"), "4294967296",
                base + "height: " + size_rule + "4294967296");
    check_error(with_camera_field("height", "[480]"), "[480]",
                base + "height: " + size_rule + "an array of 1 value");
    check_error(
        with_camera_field("fov_y_degrees", "45, \"fov\": 45"), "\"fov\"",
        base + "fov: unknown field (expected eye, target, up, fov_y_degrees, width or height)");

    const std::string no_height =
        with_roi(R"({"water_fill_clicks": {"camera": {"eye": [0, 0, 5], "target": [0, 0, 0], )"
                 R"("up": [0, 1, 0], "fov_y_degrees": 45, "width": 640}, )"
                 R"("first": [1, 1], "last": [2, 2]}})");
    check_error(no_height, R"({"eye")", base + "height: required field is missing");
    const std::string no_camera =
        with_roi(R"({"water_fill_clicks": {"first": [1, 1], "last": [2, 2]}})");
    check_error(no_camera, R"({"first")",
                "roi.water_fill_clicks.camera: required field is missing");

    std::string clicks = R"({"water_fill_clicks": {"camera": )";
    clicks += camera_text;
    const std::string outside = with_roi(clicks + R"(, "first": [320, 240], "last": [641, 10]}})");
    check_error(outside, "[641",
                "roi.water_fill_clicks.last: the pixel lies outside the image, which runs from [0, "
                "0] to [640, 480]");
    const std::string above = with_roi(clicks + R"(, "first": [320, -0.5], "last": [1, 10]}})");
    check_error(above, "[320",
                "roi.water_fill_clicks.first: the pixel lies outside the image, which runs from "
                "[0, 0] to [640, 480]");
    const std::string three = with_roi(clicks + R"(, "first": [1, 2, 3], "last": [1, 10]}})");
    check_error(three, "[1, 2, 3]",
                "roi.water_fill_clicks.first: expected an array of 2 numbers [x, y], found an "
                "array of 3 values");
}

TEST_CASE("scenario: handle errors") {
    check_error(with(any_roi, "{}"), "{}}",
                "handles: expected an array of handle groups, found an object");
    check_error(with(any_roi, "[]"), "[]",
                "handles: expected at least one handle group, found an empty array");
    check_error(with(any_roi, "[1]"), "1]", "handles[0]: expected an object, found 1");
    check_error(with_handle(R"({"translate": [0, 0, 1]})"), R"({"translate")",
                "handles[0]: expected one selection (vertices or ball), found none");
    check_error(with_handle(R"({"vertices": [1], "ball": {"center": 1, "radius": 1}})"),
                R"("ball")",
                "handles[0].ball: only one selection is allowed, and vertices is already given");
    check_error(with_handle(R"({"vertices": [1], "translation": [0, 0, 1]})"), R"("translation")",
                "handles[0].translation: unknown field (expected vertices, ball, translate, rotate "
                "or targets)");
    check_error(
        with(any_roi, R"([{"vertices": [1]}, {"vertices": [2], "translate": [0, "1", 0]}])"),
        R"("1")", "handles[1].translate[1]: expected a number, found a string");
    check_error(with_handle(R"({"vertices": [1], "translate": [0, 1]})"), "[0, 1]",
                "handles[0].translate: expected an array of 3 numbers [x, y, z], found an array of "
                "2 values");
    check_error(with_handle(R"({"vertices": []})"), "[]",
                "handles[0].vertices: expected at least one vertex index, found an empty array");
    check_error(with_handle(R"({"vertices": [5, 5]})"), "5]",
                "handles[0].vertices[1]: vertex 5 is listed twice (first at [0])");
    check_error(with_handle(R"({"ball": {"center": 1, "radius": 0}})"), "0}",
                "handles[0].ball.radius: expected a number greater than 0, found 0");
    check_error(with_handle(R"({"ball": {"center": 1, "radius": 1, "r": 1}})"), R"("r")",
                "handles[0].ball.r: unknown field (expected center or radius)");

    check_error(with_handle(R"({"vertices": [1], "rotate": {"axis": [0, 0, 0], "degrees": 5}})"),
                "[0, 0, 0]", "handles[0].rotate.axis: must not be the zero vector");
    check_error(with_handle(R"({"vertices": [1], "rotate": {"axis": [0, 0, 1]}})"), R"({"axis")",
                "handles[0].rotate.degrees: required field is missing");
    check_error(with_handle(R"({"vertices": [1], "rotate": {"degrees": 5}})"), R"({"degrees")",
                "handles[0].rotate.axis: required field is missing");
    check_error(with_handle(R"({"vertices": [1], "rotate": {"axis": [0, 0, 1], "degrees": "30"}})"),
                R"("30")", "handles[0].rotate.degrees: expected a number, found a string");
    check_error(
        with_handle(
            R"({"vertices": [1], "rotate": {"axis": [0, 0, 1], "degrees": 5, "pivot": "center"}})"),
        R"("center")",
        "handles[0].rotate.pivot: expected [x, y, z] or \"centroid\", found \"center\"");
    check_error(
        with_handle(
            R"({"vertices": [1], "rotate": {"axis": [0, 0, 1], "degrees": 5, "pivot": 5}})"),
        "5}", "handles[0].rotate.pivot: expected [x, y, z] or \"centroid\", found 5");
    check_error(
        with_handle(
            R"({"vertices": [1], "rotate": {"axis": [0, 0, 1], "degrees": 5, "pivot": [1, 2]}})"),
        "[1, 2]",
        "handles[0].rotate.pivot: expected an array of 3 numbers [x, y, z], found an array of 2 "
        "values");
    check_error(with_handle(R"({"vertices": [1], "rotate": {"axis": [0, 0, 1], "angle": 5}})"),
                R"("angle")",
                "handles[0].rotate.angle: unknown field (expected axis, degrees or pivot)");
    check_error(with_handle(R"({"vertices": [1], "rotate": [0, 0, 1]})"), "[0, 0, 1]",
                "handles[0].rotate: expected an object, found an array of 3 values");

    check_error(
        with_handle(R"({"vertices": [1, 2, 3], "targets": [[0, 0, 0], [1, 1, 1]]})"), "[[",
        "handles[0].targets: expected 3 targets, one per vertex, found an array of 2 values");
    check_error(with_handle(R"({"vertices": [1], "targets": []})"), "[]",
                "handles[0].targets: expected 1 target, one per vertex, found an empty array");
    check_error(with_handle(R"({"vertices": [1, 2], "targets": [[0, 0, 0], [1, 1]]})"), "[1, 1]",
                "handles[0].targets[1]: expected an array of 3 numbers [x, y, z], found an array "
                "of 2 values");
    check_error(with_handle(R"({"vertices": [1], "targets": {"0": [0, 0, 0]}})"), R"({"0")",
                "handles[0].targets: expected an array of [x, y, z] targets, found an object");
    check_error(with_handle(R"({"ball": {"center": 1, "radius": 1}, "targets": [[0, 0, 0]]})"),
                "[[",
                "handles[0].targets: needs a vertices list (one target per vertex), not a ball");
    check_error(with_handle(R"({"vertices": [1], "translate": [0, 0, 1], "targets": [[0, 0, 0]]})"),
                "[[", "handles[0].targets: cannot be combined with translate or rotate");
}

TEST_CASE("scenario: the solver's method selects the paper's iteration") {
    CHECK(*parse_ok(with_solver(R"({"method": "paper"})")).solver.method == "paper");
    CHECK(*parse_ok(with_solver(R"({"method": "fitted_rotations"})")).solver.method ==
          "fitted_rotations");
    CHECK_FALSE(parse_ok(with_solver("{}")).solver.method.has_value());
}

TEST_CASE("scenario: solver errors") {
    check_error(with_solver("[]"), "[]}", "solver: expected an object, found an empty array");
    check_error(
        with_solver(R"({"tolerence": 1e-5})"), R"("tolerence")",
        "solver.tolerence: unknown field (expected tolerance, max_iterations, handle_weight or "
        "method)");
    check_error(with_solver(R"({"method": "fast"})"), R"("fast")",
                R"(solver.method: expected "fitted_rotations" or "paper", found a string)");
    check_error(with_solver(R"({"method": 1})"), "1}",
                R"(solver.method: expected "fitted_rotations" or "paper", found 1)");
    const std::string positive = "expected a number greater than 0, found ";
    check_error(with_solver(R"({"tolerance": 0})"), "0}", "solver.tolerance: " + positive + "0");
    check_error(with_solver(R"({"tolerance": -1e-5})"), "-1e-5",
                "solver.tolerance: " + positive + "-1e-05");
    check_error(with_solver(R"({"tolerance": "small"})"), R"("small")",
                "solver.tolerance: " + positive + "a string");
    check_error(with_solver(R"({"handle_weight": 0})"), "0}",
                "solver.handle_weight: " + positive + "0");
    const std::string count = "expected a positive integer (at most 2147483647), found ";
    check_error(with_solver(R"({"max_iterations": 0})"), "0}",
                "solver.max_iterations: " + count + "0");
    check_error(with_solver(R"({"max_iterations": -3})"), "-3",
                "solver.max_iterations: " + count + "-3");
    check_error(with_solver(R"({"max_iterations": 50.0})"), "50.0",
                "solver.max_iterations: " + count + "50.0");
    check_error(with_solver(R"({"max_iterations": 2147483648})"), "2147483648",
                "solver.max_iterations: " + count + "2147483648");
}

TEST_CASE("scenario: errors in a multi-line file name line and column") {
    const std::string text =
        "{\n"
        "  \"mesh\": \"model:cow\",\n"
        "  \"roi\": {\"all\": true},\n"
        "  \"handles\": [\n"
        "    {\"vertices\": [1]},\n"
        "    {\"vertices\": [2],\n"
        "     \"rotate\": {\"axis\": [0, 0, 1], \"degrees\": \"30\"}}\n"
        "  ]\n"
        "}\n";
    Scenario s;
    const dfm::ToolStatus status = parse_scenario(text, "cow.json", s);
    CHECK(status.message() ==
          "cow.json:7:47: handles[1].rotate.degrees: expected a number, found a string");
}

TEST_CASE("scenario: malformed JSON") {
    const std::string good = with(any_roi, any_handles);
    check_message(good.substr(0, 30),
                  "s.json:1:31: expected '\"' to end the string started at 1:27, found the end "
                  "of the text");
    check_message(good + " x", "s.json:1:" + std::to_string(good.size() + 2) +
                                   ": expected the end of the text after the top-level value, "
                                   "found 'x'");
    check_error(with(any_roi, any_handles, R"(, "comment": "\q")"), R"(\q)",
                "expected an escape after '\\' (one of \" \\ / b f n r t u), found 'q'");
    check_message(std::string(100000, '['),
                  "s.json:1:257: arrays and objects nest deeper than 256 levels");
    const std::string deep =
        with(any_roi, any_handles, ", \"comment\": " + std::string(100000, '['));
    Scenario s;
    const dfm::ToolStatus status = parse_scenario(deep, "s.json", s);
    CHECK(status.message().starts_with("s.json:1:"));
    CHECK(status.message().ends_with(": arrays and objects nest deeper than 256 levels"));
    check_error(with(any_roi, any_handles, R"(, "mesh": "again")"), R"("mesh": "again")",
                "duplicate key \"mesh\" (first at 1:2)");
    check_error("", "", "expected a value, found the end of the text");
}

TEST_CASE("scenario: load_scenario reads files and names them in errors") {
    const std::filesystem::path dir = dfm::test::scratch_dir("scenario_load");
    const std::filesystem::path sub = dir / "edits";
    std::filesystem::create_directories(sub);

    const std::filesystem::path good = sub / "lift.json";
    dfm::test::write_text(good, with(any_roi, any_handles));
    Scenario s;
    REQUIRE(load_scenario(good, s).is_ok());
    CHECK(s.base_dir == sub);
    CHECK(s.mesh == "m.off");

    const std::filesystem::path bad = sub / "bad.json";
    dfm::test::write_text(bad, "{\n  \"mesh\": 1\n}");
    dfm::ToolStatus status = load_scenario(bad, s);
    CHECK(status.code() == DFM_ERROR_PARSE);
    CHECK(status.message() ==
          bad.string() +
              ":2:11: mesh: expected a string (a mesh file path or model:NAME), found 1");
    CHECK(s.mesh.empty());
    CHECK(s.base_dir.empty());

    status = load_scenario(sub / "missing.json", s);
    CHECK(status.code() == DFM_ERROR_NOT_FOUND);
    CHECK(status.message() == (sub / "missing.json").string() + ": no such scenario file");

    status = load_scenario(sub, s);
    CHECK(status.code() == DFM_ERROR_IO);
    CHECK(status.message() == sub.string() + ": is a directory, not a scenario file");

    status = load_scenario("/dev/null", s);
    CHECK(status.code() == DFM_ERROR_IO);
    CHECK(status.message() == "/dev/null: is not a regular file");

    const std::filesystem::path empty = sub / "empty.json";
    dfm::test::write_text(empty, "");
    status = load_scenario(empty, s);
    CHECK(status.message() == empty.string() + ":1:1: expected a value, found the end of the text");

    const std::filesystem::path locked = sub / "locked.json";
    dfm::test::write_text(locked, with(any_roi, any_handles));
    std::filesystem::permissions(locked, std::filesystem::perms::none);
    if (std::ifstream(locked)) {
        MESSAGE("this user reads files without read permission; the unreadable case is skipped");
    } else {
        status = load_scenario(locked, s);
        CHECK(status.code() == DFM_ERROR_IO);
        CHECK(status.message().starts_with(locked.string() + ": cannot open: "));
    }
    std::filesystem::permissions(locked, std::filesystem::perms::owner_all);
}

TEST_CASE("scenario: damaged scenarios give a located error or a scenario, never a crash") {
    const std::string valid =
        with(R"({"water_fill_clicks": {"camera": {"eye": [0, 0, 5], "target": [0, 0, 0], )"
             R"("up": [0, 1, 0], "fov_y_degrees": 45, "width": 64, "height": 48}, )"
             R"("first": [3, 4], "last": [5, 6]}})",
             R"([{"vertices": [1, 2], "targets": [[0, 0, 0], [1, 1, 1]]}, )"
             R"({"ball": {"center": 3, "radius": 0.5}, "translate": [0, 1, 0], )"
             R"("rotate": {"axis": [0, 0, 1], "degrees": 30, "pivot": "centroid"}}])",
             R"(, "solver": {"tolerance": 1e-5, "max_iterations": 50, "handle_weight": 1.0})");
    parse_ok(valid);
    std::mt19937 rng(7u);
    const std::string_view pieces[] = {"0",    "-1",   "1.5",       "\"x\"",      "[]",    "{}",
                                       "null", "true", "[0, 0, 0]", "4294967295", "1e999", ","};
    for (int trial = 0; trial < 5000; ++trial) {
        std::string text = valid;
        const int edits = 1 + static_cast<int>(rng() % 3);
        for (int e = 0; e < edits; ++e) {
            const std::size_t at = rng() % text.size();
            const std::size_t len = rng() % 6;
            text.replace(at, len, pieces[rng() % std::size(pieces)]);
        }
        Scenario s;
        const dfm::ToolStatus status = parse_scenario(text, "s.json", s);
        if (!status) {
            CAPTURE(text);
            REQUIRE(status.message().starts_with("s.json:"));
            REQUIRE(s.handles.empty());
        }
    }
}
