#include <doctest/doctest.h>

#include <filesystem>

#include "mesh/load.hpp"
#include "mesh/write.hpp"
#include "support/procedural_meshes.hpp"
#include "support/test_files.hpp"

using namespace dfm::mesh;

namespace {

Mesh odd_mesh() {
    Mesh m = dfm::test::make_icosphere(1);
    m.positions[0] = {0.1, 1.0 / 3.0, -2.5e-17};
    m.positions[1] = {123456.789, -0.0, 1e30};
    return m;
}

void check_same(const Mesh& a, const Mesh& b) {
    REQUIRE(a.vertex_count() == b.vertex_count());
    REQUIRE(a.face_count() == b.face_count());
    for (std::size_t i = 0; i < a.vertex_count(); ++i) CHECK(a.positions[i] == b.positions[i]);
    CHECK(a.triangles == b.triangles);
}

}  // namespace

TEST_CASE("writers round-trip exactly through every format and encoding") {
    const auto dir = dfm::test::scratch_dir("writer_round_trip");
    const Mesh m = odd_mesh();
    struct Case {
        const char* name;
        WriteOptions options;
    };
    const Case cases[] = {
        {"a.off", {}},
        {"a.obj", {}},
        {"n.obj", {.obj_normals = true}},
        {"le.ply", {.ply_encoding = PlyEncoding::binary_little_endian}},
        {"be.ply", {.ply_encoding = PlyEncoding::binary_big_endian}},
        {"ascii.ply", {.ply_encoding = PlyEncoding::ascii}},
    };
    for (const Case& c : cases) {
        CAPTURE(c.name);
        REQUIRE(save_mesh(dir / c.name, m, c.options).is_ok());
        Mesh back;
        const dfm::Status s = load_mesh(dir / c.name, back);
        REQUIRE_MESSAGE(s.is_ok(), s.message());
        check_same(m, back);
        CHECK_FALSE(std::filesystem::exists(dir / (std::string(c.name) + ".partial")));
    }
}

TEST_CASE("float PLY keeps float precision") {
    const auto dir = dfm::test::scratch_dir("writer_float");
    Mesh small = dfm::test::make_icosphere(0);
    small.positions[0] = {1.0 / 3.0, 0.0, 0.0};
    REQUIRE(save_mesh(dir / "f.ply", small, {.ply_double = false}).is_ok());
    Mesh back;
    REQUIRE(load_mesh(dir / "f.ply", back).is_ok());
    CHECK(back.positions[0].x == static_cast<double>(1.0f / 3.0f));
}

TEST_CASE("saving to an unknown extension or a missing directory fails cleanly") {
    const auto dir = dfm::test::scratch_dir("writer_errors");
    const Mesh m = dfm::test::make_icosphere(0);
    CHECK(save_mesh(dir / "a.stl", m).code() == dfm::Errc::unsupported);
    const dfm::Status s = save_mesh(dir / "no" / "such" / "a.off", m);
    CHECK(s.code() == dfm::Errc::io_error);
    CHECK(s.message().find("a.off: cannot create") != std::string::npos);
}

TEST_CASE("a failed save leaves the existing file intact") {
    const auto dir = dfm::test::scratch_dir("writer_keep");
    const Mesh m = dfm::test::make_icosphere(0);
    REQUIRE(save_mesh(dir / "keep.off", m).is_ok());
    const std::string before = dfm::test::read_text(dir / "keep.off");
    std::filesystem::create_directory(dir / "keep.off.partial");
    CHECK_FALSE(save_mesh(dir / "keep.off", dfm::test::make_icosphere(1)).is_ok());
    CHECK(dfm::test::read_text(dir / "keep.off") == before);
}
