#include <doctest/doctest.h>

#include <glm/geometric.hpp>
#include <string>
#include <vector>

#include "dualform/edit_chain.hpp"
#include "support/test_files.hpp"

using namespace dfm;

namespace {

std::string scenario(const char* name) {
    return (test::data_dir().parent_path() / "scenarios" / name).string();
}

std::size_t moved(const cli::EditChain& chain) {
    std::size_t n = 0;
    for (std::size_t v = 0; v < chain.rest.vertex_count(); ++v) {
        if (chain.deformed[v] != chain.rest.positions[v]) ++n;
    }
    return n;
}

}  // namespace

TEST_CASE("edit chain: two cow edits, the second baked on the first, both show") {
    const std::vector<std::string> leg = {scenario("cow-front-leg-step.json")};
    const std::vector<std::string> both = {scenario("cow-front-leg-step.json"),
                                           scenario("cow-tail-swing.json")};
    cli::EditChain one, two;
    REQUIRE(cli::run_edit_chain(leg, one).is_ok());
    REQUIRE(cli::run_edit_chain(both, two).is_ok());
    CHECK(two.unconverged == 0);
    CHECK(moved(one) > 50);
    CHECK(moved(two) > moved(one) + 50);
    // The leg, baked first, stays where its own edit left it: up to the warm
    // step dfm_session_bake takes to finish the result (far below the
    // stopping rule's 1e-5 of the cow's diagonal, about 1.2).
    for (std::size_t v = 0; v < one.rest.vertex_count(); ++v) {
        if (one.marks[v] == cli::mark_handle) {
            CHECK(glm::distance(one.deformed[v], two.deformed[v]) < 1e-7);
        }
    }
    std::size_t marked = 0;
    for (std::uint8_t m : two.marks) marked += m != 0;
    CHECK(marked > 250);
}

TEST_CASE("edit chain: edits of different meshes are refused, naming the edit") {
    const std::vector<std::string> mixed = {scenario("cow-front-leg-step.json"),
                                            scenario("triceratops-horn-rotate.json")};
    cli::EditChain chain;
    const dfm::ToolStatus s = cli::run_edit_chain(mixed, chain);
    REQUIRE_FALSE(s.is_ok());
    CHECK(s.message().find("edit 2 of 2") != std::string::npos);
    CHECK(s.message().find("model:triceratops") != std::string::npos);
}
