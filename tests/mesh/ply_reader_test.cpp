#include <doctest/doctest.h>

#include <bit>
#include <cstdint>
#include <cstring>
#include <string>

#include "mesh/load.hpp"

using dfm::Errc;
using namespace dfm::mesh;

namespace {

Mesh parse_ok(std::string_view bytes) {
    Mesh m;
    const dfm::Status s = parse_mesh(bytes, FileFormat::ply, "t.ply", m);
    REQUIRE_MESSAGE(s.is_ok(), s.message());
    return m;
}

dfm::Status parse_fail(std::string_view bytes) {
    Mesh m;
    const dfm::Status s = parse_mesh(bytes, FileFormat::ply, "t.ply", m);
    CHECK_FALSE(s.is_ok());
    CHECK(m.vertex_count() == 0);
    return s;
}

// Appends `v` in the chosen byte order.
template <typename T>
void put(std::string& out, T v, bool big_endian) {
    char raw[sizeof(T)];
    std::memcpy(raw, &v, sizeof(T));
    if (big_endian != (std::endian::native == std::endian::big)) {
        for (std::size_t i = 0; i < sizeof(T) / 2; ++i) std::swap(raw[i], raw[sizeof(T) - 1 - i]);
    }
    out.append(raw, sizeof(T));
}

// A square as two triangles, with extra properties and an extra element that
// the reader must step over.
std::string binary_square(bool big_endian) {
    std::string s = std::string("ply\nformat ") +
                    (big_endian ? "binary_big_endian" : "binary_little_endian") +
                    " 1.0\ncomment extra stuff\nelement vertex 4\nproperty double x\n"
                    "property float y\nproperty uchar red\nproperty short z\n"
                    "property list uchar int16 junk\n"
                    "element face 2\nproperty int flags\nproperty list ushort uint vertex_indices\n"
                    "element edge 1\nproperty int vertex1\nproperty int vertex2\nend_header\n";
    const double xy[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    for (auto& p : xy) {
        put(s, p[0], big_endian);
        put(s, static_cast<float>(p[1]), big_endian);
        put(s, std::uint8_t{200}, big_endian);
        put(s, std::int16_t{7}, big_endian);
        put(s, std::uint8_t{2}, big_endian);
        put(s, std::int16_t{-1}, big_endian);
        put(s, std::int16_t{-2}, big_endian);
    }
    const std::uint32_t faces[2][3] = {{0, 1, 2}, {0, 2, 3}};
    for (auto& f : faces) {
        put(s, std::int32_t{42}, big_endian);
        put(s, std::uint16_t{3}, big_endian);
        for (std::uint32_t v : f) put(s, v, big_endian);
    }
    put(s, std::int32_t{0}, big_endian);
    put(s, std::int32_t{1}, big_endian);
    return s;
}

}  // namespace

TEST_CASE("PLY: ascii with extra properties, a quad and an extra element") {
    const Mesh m = parse_ok(
        "ply\nformat ascii 1.0\ncomment hello\nobj_info x\nelement vertex 4\nproperty float x\n"
        "property float y\nproperty float z\nproperty uchar red\nelement face 1\n"
        "property list uchar int vertex_index\nelement material 1\nproperty float shine\n"
        "end_header\n0 0 0 1\n1 0 0 2\n1 1 0 3\n0 1 0.5 4\n4 0 1 2 3\n0.25\n");
    REQUIRE(m.vertex_count() == 4);
    CHECK(m.positions[3] == glm::dvec3(0, 1, 0.5));
    REQUIRE(m.face_count() == 2);
    CHECK(m.triangles[1] == Triangle{0, 2, 3});
}

TEST_CASE("PLY: binary little and big endian, any scalar and list types") {
    for (bool big : {false, true}) {
        CAPTURE(big);
        const Mesh m = parse_ok(binary_square(big));
        REQUIRE(m.vertex_count() == 4);
        CHECK(m.positions[2] == glm::dvec3(1, 1, 7));
        REQUIRE(m.face_count() == 2);
        CHECK(m.triangles[0] == Triangle{0, 1, 2});
        CHECK(m.triangles[1] == Triangle{0, 2, 3});
    }
}

TEST_CASE("PLY: truncated binary data is located by byte offset") {
    std::string s = binary_square(false);
    s.resize(s.size() - 12);
    const dfm::Status st = parse_fail(s);
    CHECK(st.code() == Errc::parse_error);
    CHECK(st.message().find("t.ply: byte ") == 0);
    CHECK(st.message().find("face 1 property 'vertex_indices': truncated") != std::string::npos);
}

TEST_CASE("PLY: header errors are located") {
    CHECK(parse_fail("plx\n").message() == "t.ply:1: not a PLY file: the first line must be 'ply'");
    CHECK(parse_fail("ply\nformat ascii 1.0\nelement vertex 1\nproperty quad x\nend_header\n")
              .message() == "t.ply:4: property: unknown value type 'quad'");
    CHECK(parse_fail("ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n").message() ==
          "t.ply:4: truncated header: no 'end_header' line");
    CHECK(parse_fail("ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
                     "end_header\n0 0\n")
              .message() == "t.ply:3: element 'vertex' has no 'z' property");
    CHECK(parse_fail("ply\nformat ascii 1.0\nelement vertex 99999999999\nproperty float x\n"
                     "property float y\nproperty float z\nend_header\n0 0 0\n")
              .message()
              .find("t.ply:3: element 'vertex' declares 99999999999 records") == 0);
    CHECK(parse_fail("ply\nformat binary_middle_endian 1.0\nend_header\n").code() ==
          Errc::parse_error);
}

TEST_CASE("PLY: bad values in the body") {
    const std::string head =
        "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
        "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n";
    CHECK(parse_fail(head + "0 0 0\n1 0 0\n0 1 0\n3 0 1 5\n").message() ==
          "t.ply:13: face 0: vertex index 5 is out of range (the mesh has 3 vertices, indexed from "
          "0)");
    CHECK(parse_fail(head + "0 0 0\n1 q 0\n0 1 0\n3 0 1 2\n").message() ==
          "t.ply:11: vertex 1 property 'y': 'q' is not a number");
    CHECK(parse_fail(head + "0 0 0\n1 0 0\n0 1 0\n200 0 1 2\n").code() == Errc::out_of_range);
    CHECK(parse_fail(head + "0 0 0\n1 0 0\n0 1 0\n-3 0 1 2\n").message() ==
          "t.ply:13: face 0 property 'vertex_indices': list count -3 is negative");
}

TEST_CASE("PLY: an element without properties holds nothing, whatever its count") {
    // Once a hang: the reader stepped through 10^12 empty records.
    const Mesh m = parse_ok(
        "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
        "property float z\nelement junk 999999999999\nend_header\n0 0 0\n1 0 0\n0 1 0\n");
    CHECK(m.vertex_count() == 3);
    CHECK(m.face_count() == 0);
}
