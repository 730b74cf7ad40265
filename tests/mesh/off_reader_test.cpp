#include <doctest/doctest.h>

#include "mesh/load.hpp"

using dfm::Errc;
using namespace dfm::mesh;

namespace {

Mesh parse_ok(std::string_view text, LoadReport* report = nullptr) {
    Mesh m;
    const dfm::Status s = parse_mesh(text, FileFormat::off, "t.off", m, report);
    REQUIRE_MESSAGE(s.is_ok(), s.message());
    return m;
}

dfm::Status parse_fail(std::string_view text) {
    Mesh m;
    const dfm::Status s = parse_mesh(text, FileFormat::off, "t.off", m);
    CHECK_FALSE(s.is_ok());
    CHECK(m.vertex_count() == 0);
    CHECK(m.face_count() == 0);
    return s;
}

}  // namespace

TEST_CASE("OFF: a tetrahedron with comments, blank lines and CRLF") {
    const Mesh m = parse_ok(
        "OFF\r\n# a comment\r\n\r\n4 4 6\r\n0 0 0\r\n1 0 0 # trailing\r\n0 1 0\r\n0 0 1\r\n"
        "3 0 2 1\r\n3 0 1 3\r\n3 0 3 2\r\n3 1 2 3\r\n");
    REQUIRE(m.vertex_count() == 4);
    REQUIRE(m.face_count() == 4);
    CHECK(m.positions[1] == glm::dvec3(1, 0, 0));
    CHECK(m.triangles[3] == Triangle{1, 2, 3});
}

TEST_CASE("OFF: counts on the keyword line") {
    const Mesh m = parse_ok("OFF 3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
    CHECK(m.face_count() == 1);
}

TEST_CASE("OFF: COFF colours, NOFF normals and face colours are skipped") {
    const Mesh c = parse_ok(
        "COFF\n3 1 0\n0 0 0 255 0 0 255\n1 0 0 0 255 0 255\n0 1 0 0 0 255 255\n"
        "3 0 1 2 0.5 0.5 0.5\n");
    CHECK(c.positions[2] == glm::dvec3(0, 1, 0));
    const Mesh n = parse_ok("NOFF\n3 1 0\n0 0 0 0 0 1\n1 0 0 0 0 1\n0 1 0 0 0 1\n3 0 1 2\n");
    CHECK(n.face_count() == 1);
    const Mesh st = parse_ok(
        "STCNOFF\n3 1 0\n0 0 0 0 0 1 1 1 1 0 0\n1 0 0 0 0 1 1 1 1 1 0\n"
        "0 1 0 0 0 1 1 1 1 0 1\n3 0 1 2\n");
    CHECK(st.vertex_count() == 3);
}

TEST_CASE("OFF: polygons are fanned into triangles") {
    LoadReport report;
    const Mesh m = parse_ok(
        "OFF\n5 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n0.5 1.5 0\n4 0 1 2 3\n3 3 2 4\n", &report);
    REQUIRE(m.face_count() == 3);
    CHECK(m.triangles[0] == Triangle{0, 1, 2});
    CHECK(m.triangles[1] == Triangle{0, 2, 3});
    CHECK(m.triangles[2] == Triangle{3, 2, 4});
    CHECK(report.polygons == 2);
    CHECK(report.triangulated_polygons == 1);
}

TEST_CASE("OFF: a face repeating a vertex is dropped with a located warning") {
    LoadReport report;
    const Mesh m = parse_ok("OFF\n4 2 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 1 1\n3 0 1 2\n", &report);
    CHECK(m.face_count() == 1);
    CHECK(report.dropped_faces == 1);
    REQUIRE(report.warnings.size() == 1);
    CHECK(report.warnings[0].find("t.off:7: face 0: repeats a vertex") == 0);
}

TEST_CASE("OFF: exponents, signs and integers as coordinates") {
    const Mesh m = parse_ok("OFF\n3 1 0\n-1.5e-8 +2 3E2\n1 0 0\n0 1 0\n3 0 1 2\n");
    CHECK(m.positions[0] == glm::dvec3(-1.5e-8, 2, 300));
}

TEST_CASE("OFF: errors name the file, the line and the element") {
    CHECK(parse_fail("OFF\n3 1 0\n0 0 0\n1 x 0\n0 1 0\n3 0 1 2\n").message() ==
          "t.off:4: vertex 1: coordinate 'x' is not a number");
    CHECK(parse_fail("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n").message() ==
          "t.off:6: face 0: vertex index 3 is out of range (the mesh has 3 vertices, indexed from "
          "0)");
    CHECK(parse_fail("OFF\n3 1 0\n0 0 0\n1 0 nan\n0 1 0\n3 0 1 2\n").message() ==
          "t.off:4: vertex 1: coordinate 'nan' is not a finite number");
    CHECK(parse_fail("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n2 0 1\n").message() ==
          "t.off:6: face 0: has 2 vertices; a face needs at least 3");
    CHECK(parse_fail("OFF\n3 2 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n").message() ==
          "t.off:6: truncated: expected 2 faces, the file ends after 1");
    CHECK(parse_fail("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2.0\n").code() == Errc::parse_error);
    CHECK(parse_fail("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 -1\n").code() == Errc::out_of_range);
}

TEST_CASE("OFF: absurd counts are refused before anything is allocated") {
    const dfm::Status s = parse_fail("OFF\n4000000000 4000000000 0\n0 0 0\n");
    CHECK(s.code() == Errc::parse_error);
    CHECK(s.message().find("t.off:2: the header declares 4000000000 vertices") == 0);
    CHECK(parse_fail("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n1000000000 0 1 2\n").code() ==
          Errc::out_of_range);
}

TEST_CASE("OFF: unsupported variants say so") {
    CHECK(parse_fail("4OFF\n1 0 0\n0 0 0 1\n").code() == Errc::unsupported);
    CHECK(parse_fail("OFF BINARY\n").code() == Errc::unsupported);
    CHECK(parse_fail("PFF\n3 1 0\n").code() == Errc::parse_error);
    CHECK(parse_fail("# only a comment\n").message() ==
          "t.off:1: no OFF header: the file is empty");
}
