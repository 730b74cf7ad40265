// Bad values in the fields tests/tools/scenario_test.cpp does not reach:
// each must be refused with an error that names the field's full path.

#include <string>
#include <string_view>

#include <doctest/doctest.h>

#include "dualform/scenario.hpp"

namespace dfm::test {

namespace {

struct BadScenario {
    std::string_view field;  // the path the error must name
    std::string_view roi;
    std::string_view handles;
    std::string_view more = "";
};

constexpr std::string_view all = R"({"all": true})";
constexpr std::string_view one_handle = R"([{"vertices": [7]}])";

// One row per field and kind of bad value.
constexpr BadScenario bad_scenarios[] = {
    {"description", all, one_handle, R"(, "description": 42)"},
    {"description", all, one_handle, R"(, "description": null)"},
    {"roi.all", R"({"all": false})", one_handle},
    {"roi.all", R"({"all": 1})", one_handle},
    {"roi.vertices[1]", R"({"vertices": [3, -1]})", one_handle},
    {"roi.vertices[0]", R"({"vertices": [2.5]})", one_handle},
    {"roi.vertices[0]", R"({"vertices": [4294967296]})", one_handle},
    {"roi.vertices", R"({"vertices": []})", one_handle},
    {"roi.ball.center", R"({"ball": {"center": -3, "radius": 0.1}})", one_handle},
    {"roi.ball.radius", R"({"ball": {"center": 3, "radius": -0.1}})", one_handle},
    {"roi.ball.radius", R"({"ball": {"center": 3}})", one_handle},
    {"roi.water_fill.first", R"({"water_fill": {"first": "a", "last": 2}})", one_handle},
    {"roi.water_fill.last", R"({"water_fill": {"first": 1, "last": 1.5}})", one_handle},
    {"handles[0].vertices[0]", all, R"([{"vertices": [-7]}])"},
    {"handles[0].vertices[0]", all, R"([{"vertices": [true]}])"},
    {"handles[0].ball.center", all, R"([{"ball": {"center": 0.5, "radius": 0.1}}])"},
    {"handles[0].ball.center", all, R"([{"ball": {"radius": 0.1}}])"},
    {"handles[0].translate", all, R"([{"vertices": [7], "translate": 0.1}])"},
    {"handles[0].translate[2]", all, R"([{"vertices": [7], "translate": [0, 0, "1"]}])"},
    {"handles[0].rotate.pivot", all,
     R"([{"vertices": [7], "rotate": {"axis": [0, 0, 1], "degrees": 9, "pivot": [1, 2]}}])"},
    {"handles[0].rotate.axis", all,
     R"([{"vertices": [7], "rotate": {"axis": [0, 1], "degrees": 9}}])"},
    {"handles[1].vertices", all, R"([{"vertices": [7]}, {"vertices": {}}])"},
    {"solver.tolerance", all, one_handle, R"(, "solver": {"tolerance": -1})"},
    {"solver.max_iterations", all, one_handle, R"(, "solver": {"max_iterations": 2.5})"},
    {"solver.handle_weight", all, one_handle, R"(, "solver": {"handle_weight": "1"})"},
};

}  // namespace

TEST_CASE("scenario misuse: every bad field is refused with its path named") {
    for (const BadScenario& bad : bad_scenarios) {
        std::string text = R"({"mesh": "m.off", "roi": )";
        text += bad.roi;
        text += R"(, "handles": )";
        text += bad.handles;
        text += bad.more;
        text += "}";
        CAPTURE(text);
        cli::Scenario scenario;
        const dfm::ToolStatus status = cli::parse_scenario(text, "s.json", scenario);
        REQUIRE_FALSE(status.is_ok());
        CHECK(status.code() == DFM_ERROR_PARSE);
        const std::string named = ": " + std::string(bad.field) + ": ";
        CHECK_MESSAGE(status.message().find(named) != std::string::npos, status.message());
        CHECK(status.message().starts_with("s.json:1:"));
    }
}

TEST_CASE("scenario misuse: a number beyond a double is refused naming its field") {
    cli::Scenario scenario;
    const dfm::ToolStatus status = cli::parse_scenario(
        R"({"mesh": "m.off", "roi": {"all": true}, "handles": [{"vertices": [7]}], )"
        R"("subdivide": 1e999})",
        "s.json", scenario);
    CHECK(status.code() == DFM_ERROR_PARSE);
    CHECK(status.message() ==
          "s.json:1:86: subdivide: the number 1e999 is beyond the range of a double");
    const dfm::ToolStatus nested = cli::parse_scenario(
        R"({"mesh": "m.off", "roi": {"ball": {"center": 0, "radius": -1e400}}, )"
        R"("handles": [{"vertices": [7]}]})",
        "s.json", scenario);
    CHECK(nested.message() ==
          "s.json:1:59: roi.ball.radius: the number -1e400 is beyond the range of a double");
}

}  // namespace dfm::test
