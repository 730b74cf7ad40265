#include <doctest/doctest.h>

#include "mesh/load.hpp"

using dfm::Errc;
using namespace dfm::mesh;

namespace {

Mesh parse_ok(std::string_view text, LoadReport* report = nullptr) {
    Mesh m;
    const dfm::Status s = parse_mesh(text, FileFormat::obj, "t.obj", m, report);
    REQUIRE_MESSAGE(s.is_ok(), s.message());
    return m;
}

dfm::Status parse_fail(std::string_view text) {
    Mesh m;
    const dfm::Status s = parse_mesh(text, FileFormat::obj, "t.obj", m);
    CHECK_FALSE(s.is_ok());
    CHECK(m.vertex_count() == 0);
    return s;
}

constexpr std::string_view square =
    "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvn 0 0 1\n";

}  // namespace

TEST_CASE("OBJ: every corner form gives the same triangles") {
    for (const char* faces :
         {"f 1 2 3\nf 1 3 4\n", "f 1/1 2/2 3/3\nf 1/1 3/3 4/4\n",
          "f 1//1 2//1 3//1\nf 1//1 3//1 4//1\n", "f 1/1/1 2/2/1 3/3/1\nf 1/1/1 3/3/1 4/4/1\n",
          "f -4/-4/-1 -3/-3/-1 -2/-2/-1\nf -4 -2 -1\n"}) {
        CAPTURE(faces);
        const Mesh m = parse_ok(std::string(square) + faces);
        REQUIRE(m.face_count() == 2);
        CHECK(m.triangles[0] == Triangle{0, 1, 2});
        CHECK(m.triangles[1] == Triangle{0, 2, 3});
    }
}

TEST_CASE("OBJ: negative indices count back from the vertices defined so far") {
    const Mesh m = parse_ok("v 0 0 0\nv 1 0 0\nv 0 1 0\nf -3 -2 -1\nv 1 1 0\nf -3 -1 -2\n");
    REQUIRE(m.face_count() == 2);
    CHECK(m.triangles[1] == Triangle{1, 3, 2});
}

TEST_CASE("OBJ: polygons, groups, materials, lines and unknown keywords") {
    LoadReport report;
    const Mesh m = parse_ok(
        "mtllib a.mtl\no thing\ng part\nusemtl red\ns 1\nv 0 0 0 1\nv 1 0 0\nv 1 1 0 0.5 0.5 0.5\n"
        "v 0 1 0\nv 0.5 2 0\nf 1 2 3 5 4\nl 1 2\np 3\nfoo bar\nfoo baz\n",
        &report);
    CHECK(m.vertex_count() == 5);
    CHECK(m.face_count() == 3);
    CHECK(report.triangulated_polygons == 1);
    REQUIRE(report.warnings.size() == 1);
    CHECK(report.warnings[0] == "t.obj:14: unknown keyword 'foo' skipped");
}

TEST_CASE("OBJ: errors are located") {
    CHECK(parse_fail("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n").message() ==
          "t.obj:4: face 0: vertex index 0 is invalid (OBJ counts from 1)");
    CHECK(parse_fail("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n").message() ==
          "t.obj:4: face 0: vertex index 4 is out of range (3 defined so far)");
    CHECK(parse_fail("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 -4\n").code() == Errc::out_of_range);
    CHECK(parse_fail("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1/1 2/1 3/1\n").message() ==
          "t.obj:4: face 0: texture coordinate index 1 is out of range (0 defined so far)");
    CHECK(parse_fail("v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf 1//2 2//1 3//1\n").code() ==
          Errc::out_of_range);
    CHECK(parse_fail("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1// 2 3\n").message() ==
          "t.obj:4: face 0: malformed corner '1//'");
    CHECK(parse_fail("v 0 0\n").message() == "t.obj:1: vertex 0: expected 3 numbers, found 2");
    CHECK(parse_fail("v 0 0 inf\n").message() == "t.obj:1: vertex 0: 'inf' is not a finite number");
    CHECK(parse_fail("v 0 0 0\nv 1 0 0\nf 1 2\n").message() ==
          "t.obj:3: face 0: has 2 vertices; a face needs at least 3");
    CHECK(parse_fail("hello world\n").message() ==
          "t.obj:1: no vertex ('v') lines: not an OBJ mesh");
    CHECK(parse_fail("\n# nothing\n").code() == Errc::parse_error);
}
