// Every input the fuzz targets ever found (tests/data/fuzz-regressions/,
// one file per finding, named after what it broke) and the malformed-mesh
// corpus replayed through the fuzz targets' parse functions and contracts,
// so a fixed bug stays fixed without clang.

#include <filesystem>
#include <string>
#include <vector>

#include <doctest/doctest.h>

#include "fuzz/load_contract.hpp"
#include "fuzz/scenario_contract.hpp"
#include "support/test_files.hpp"

namespace dfm::test {

namespace {

std::vector<std::filesystem::path> replayed_inputs() {
    std::vector<std::filesystem::path> files;
    for (const char* folder : {"fuzz-regressions", "malformed"}) {
        for (const auto& entry : std::filesystem::directory_iterator(data_dir() / folder)) {
            const std::filesystem::path& p = entry.path();
            const bool input = p.extension() == ".json" || mesh::format_from_extension(p);
            if (entry.is_regular_file() && input) files.push_back(p);
        }
    }
    return files;
}

}  // namespace

TEST_CASE("fuzz regressions: every past finding loads or fails with a located error") {
    const std::vector<std::filesystem::path> files = replayed_inputs();
    for (const std::filesystem::path& file : files) {
        const std::string name = file.filename().string();
        const std::string bytes = read_text(file);
        CAPTURE(name);
        if (file.extension() == ".json") {
            cli::Scenario scenario;
            const dfm::ToolStatus status = cli::parse_scenario(bytes, name, scenario);
            CHECK_MESSAGE(scenario_contract_holds(status, scenario, name), status.message());
        } else {
            const auto format = mesh::format_from_extension(file);
            REQUIRE(format.has_value());
            mesh::Mesh mesh;
            mesh::LoadReport report;
            const Status status = mesh::parse_mesh(bytes, *format, name, mesh, &report);
            CHECK_MESSAGE(load_contract_holds(status, mesh, report, name), status.message());
        }
    }
    MESSAGE(files.size() << " inputs replayed");
    CHECK(files.size() >= 100);
}

}  // namespace dfm::test
