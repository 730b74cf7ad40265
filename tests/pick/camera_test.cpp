#include <doctest/doctest.h>

#include <cmath>
#include <string>

#include <glm/geometric.hpp>

#include "pick/camera.hpp"

using namespace dfm::pick;

namespace {

Camera test_camera() {
    Camera c;
    c.eye = {1.0, 2.0, 5.0};
    c.target = {0.0, 0.5, 0.0};
    c.up = {0.0, 1.0, 0.0};
    c.fov_y_degrees = 50.0;
    c.width = 640;
    c.height = 480;
    return c;
}

}  // namespace

TEST_CASE("pick: camera centre pixel looks straight at the target") {
    const Camera c = test_camera();
    REQUIRE(check_camera(c).is_ok());
    const Ray r = pixel_ray(c, {320.0, 240.0});
    CHECK(glm::length(r.origin - c.eye) == doctest::Approx(0.0));
    CHECK(glm::length(r.direction - glm::normalize(c.target - c.eye)) < 1e-12);
}

TEST_CASE("pick: camera image edges span the vertical field of view, y down") {
    Camera c = test_camera();
    c.eye = {0.0, 0.0, 3.0};
    c.target = {0.0, 0.0, 0.0};
    const Ray top = pixel_ray(c, {320.0, 0.0});
    const Ray bottom = pixel_ray(c, {320.0, 480.0});
    CHECK(top.direction.y > 0.0);
    CHECK(bottom.direction.y < 0.0);
    const double degrees =
        std::acos(glm::dot(top.direction, bottom.direction)) * 180.0 / std::acos(-1.0);
    CHECK(degrees == doctest::Approx(50.0));
    CHECK(pixel_ray(c, {640.0, 240.0}).direction.x > 0.0);  // x to the right
}

TEST_CASE("pick: camera project inverts pixel_ray") {
    const Camera c = test_camera();
    for (const glm::dvec2 pixel :
         {glm::dvec2(0, 0), glm::dvec2(17.5, 401.25), glm::dvec2(640, 480)}) {
        const Ray r = pixel_ray(c, pixel);
        const auto back = project(c, r.origin + 3.7 * r.direction);
        REQUIRE(back.has_value());
        CHECK(glm::length(*back - pixel) < 1e-9);
    }
    CHECK_FALSE(project(c, c.eye - (c.target - c.eye)).has_value());
}

TEST_CASE("pick: check_camera names what is wrong") {
    Camera c = test_camera();
    c.target = c.eye;
    CHECK(check_camera(c).message().find("target") != std::string::npos);
    c = test_camera();
    c.up = c.target - c.eye;
    CHECK(check_camera(c).message().find("up") != std::string::npos);
    c = test_camera();
    c.fov_y_degrees = 180.0;
    CHECK(check_camera(c).message().find("fov_y_degrees") != std::string::npos);
    c = test_camera();
    c.height = 0;
    CHECK(check_camera(c).message().find("height") != std::string::npos);
    c = test_camera();
    c.eye.x = std::nan("");
    CHECK(check_camera(c).message().find("finite") != std::string::npos);
}
