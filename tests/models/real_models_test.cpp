#include <doctest/doctest.h>

#include <string>

#include "environment/host_environment.hpp"
#include "mesh/load.hpp"
#include "mesh/model_cache.hpp"
#include "mesh/normals.hpp"
#include "mesh/summary.hpp"
#include "mesh/write.hpp"
#include "support/model_variants.hpp"
#include "support/test_files.hpp"

using namespace dfm::mesh;

namespace {

Mesh load_model(const std::string& name) {
    std::filesystem::path path;
    const dfm::Status r =
        resolve_mesh_spec("model:" + name, {}, dfm::tools::models_folder_from_environment(), path);
    REQUIRE_MESSAGE(r.is_ok(), r.message());
    Mesh m;
    const dfm::Status s = load_mesh(path, m);
    REQUIRE_MESSAGE(s.is_ok(), s.message());
    return m;
}

}  // namespace

TEST_CASE("the paper's models load with their known counts") {
    struct Known {
        const char* name;
        std::size_t vertices;
        std::size_t faces;
    };
    for (const Known k :
         {Known{"cow", 2904, 5804}, Known{"dino", 3916, 7828}, Known{"camel", 9770, 19536},
          Known{"triceratops", 2832, 5660}, Known{"armadillo", 26002, 52000}}) {
        CAPTURE(k.name);
        const MeshSummary s = summarize(load_model(k.name));
        CHECK(s.vertices == k.vertices);
        CHECK(s.faces == k.faces);
        CHECK(s.closed);
        CHECK(s.components == 1);
        CHECK(s.non_manifold_edges == 0);
        CHECK(s.inconsistent_edges == 0);
        CHECK(s.vertices - s.edges + s.faces == 2);
    }
}

TEST_CASE("the cow reads back identically from every format and encoding") {
    const Mesh cow = load_model("cow");
    const auto dir = dfm::test::scratch_dir("cow_variants");
    const std::vector<std::filesystem::path> files = dfm::test::write_model_variants(cow, dir);
    CHECK(files.size() == 6);
    for (const auto& f : files) {
        CAPTURE(f.string());
        Mesh back;
        const dfm::Status s = load_mesh(f, back);
        REQUIRE_MESSAGE(s.is_ok(), s.message());
        REQUIRE(back.vertex_count() == cow.vertex_count());
        CHECK(back.positions == cow.positions);
        CHECK(back.triangles == cow.triangles);
    }
}

TEST_CASE("every mesh in the model cache loads without error") {
    std::size_t count = 0;
    for (const auto& entry :
         std::filesystem::directory_iterator(dfm::tools::models_folder_from_environment())) {
        if (entry.path().extension() != ".off") continue;
        CAPTURE(entry.path().string());
        Mesh m;
        LoadReport report;
        const dfm::Status s = load_mesh(entry.path(), m, &report);
        CHECK_MESSAGE(s.is_ok(), s.message());
        ++count;
    }
    CHECK(count >= 100);
}
