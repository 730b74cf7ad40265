#include <doctest/doctest.h>

#include <filesystem>
#include <string>

#include "mesh/load.hpp"
#include "support/test_files.hpp"

// FBX is recognised in every build; a build without Assimp (DUALFORM_FBX
// off) refuses it by name. fbx_test.cpp has the rest, with FBX.
namespace {

using namespace dfm;

std::filesystem::path small(std::string_view name) {
    return test::data_dir() / "fbx" / std::string(name);
}

}  // namespace

TEST_CASE("fbx: the content tells FBX when the extension does not") {
    std::string bytes;
    REQUIRE(mesh::read_file_bytes(small("strip.fbx"), bytes));
    CHECK(mesh::format_from_content(bytes) == mesh::FileFormat::fbx);
    REQUIRE(mesh::read_file_bytes(small("strip-ascii.fbx"), bytes));
    CHECK(mesh::format_from_content(bytes) == mesh::FileFormat::fbx);
    CHECK(mesh::format_from_extension("a/B.FBX") == mesh::FileFormat::fbx);
    if (!mesh::fbx_supported()) {
        mesh::Mesh m;
        const Status s = mesh::load_mesh(small("strip.fbx"), m);
        CHECK(s.code() == Errc::unsupported);
        CHECK(s.message().find("built without Assimp") != std::string::npos);
        return;
    }
    const auto scratch = test::scratch_dir("fbx_sniff");
    std::filesystem::copy_file(small("strip.fbx"), scratch / "strip.bin");
    mesh::Mesh m;
    const Status s = mesh::load_mesh(scratch / "strip.bin", m);
    CHECK_MESSAGE(s.is_ok(), s.message());
    CHECK(m.vertex_count() == 21);
}
