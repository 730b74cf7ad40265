#include <doctest/doctest.h>

#include <algorithm>
#include <sstream>
#include <string>
#include <vector>

#include "mesh/load.hpp"
#include "support/test_files.hpp"

// Every file in tests/data/malformed must fail to load with the error that
// EXPECTED.tsv names: code, location right after the path, and a piece of
// the description.
namespace {

struct Expectation {
    std::string file;
    std::string code;
    std::string location;
    std::string text;
};

std::vector<Expectation> read_manifest(const std::filesystem::path& path) {
    std::vector<Expectation> out;
    std::istringstream lines(dfm::test::read_text(path));
    std::string line;
    while (std::getline(lines, line)) {
        if (line.empty()) continue;
        std::vector<std::string> cols;
        std::size_t start = 0;
        for (std::size_t tab; (tab = line.find('\t', start)) != std::string::npos;
             start = tab + 1) {
            cols.push_back(line.substr(start, tab - start));
        }
        cols.push_back(line.substr(start));
        REQUIRE_MESSAGE(cols.size() == 4, "bad manifest line: ", line);
        out.push_back({cols[0], cols[1], cols[2], cols[3]});
    }
    return out;
}

}  // namespace

TEST_CASE("malformed corpus: each file fails with its expected, located error") {
    const auto dir = dfm::test::data_dir() / "malformed";
    const std::vector<Expectation> cases = read_manifest(dir / "EXPECTED.tsv");
    CHECK(cases.size() >= 30);
    for (const Expectation& e : cases) {
        CAPTURE(e.file);
        // A build without FBX refuses those files as a whole (fbx_test.cpp).
        if (e.file.starts_with("fbx-") && !dfm::mesh::fbx_supported()) continue;
        const std::filesystem::path path = dir / e.file;
        dfm::mesh::Mesh m;
        const dfm::Status s = dfm::mesh::load_mesh(path, m);
        CAPTURE(s.message());
        REQUIRE_FALSE(s.is_ok());
        CHECK(std::string(dfm::errc_name(s.code())) == e.code);
        CHECK(s.message().rfind(path.string() + e.location, 0) == 0);
        CHECK(s.message().find(e.text) != std::string::npos);
        CHECK(m.vertex_count() == 0);
        CHECK(m.face_count() == 0);
    }
}

TEST_CASE("malformed corpus: every file in the folder is in the manifest") {
    const auto dir = dfm::test::data_dir() / "malformed";
    const std::vector<Expectation> cases = read_manifest(dir / "EXPECTED.tsv");
    for (const auto& entry : std::filesystem::directory_iterator(dir)) {
        const std::string name = entry.path().filename().string();
        if (name == "EXPECTED.tsv") continue;
        CAPTURE(name);
        CHECK(std::any_of(cases.begin(), cases.end(),
                          [&](const Expectation& e) { return e.file == name; }));
    }
}
