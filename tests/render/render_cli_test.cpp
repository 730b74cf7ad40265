#include <doctest/doctest.h>

#include <string>

#include "support/run_process.hpp"
#include "support/test_files.hpp"

using namespace dfm::test;

namespace {

std::string scenario(const char* name) {
    return (data_dir().parent_path() / "scenarios" / name).string();
}

// Width and height from a PNG's IHDR (big endian, bytes 16 and 20).
std::pair<unsigned, unsigned> png_size(const std::string& bytes) {
    auto word = [&](std::size_t at) {
        unsigned v = 0;
        for (std::size_t i = 0; i < 4; ++i)
            v = (v << 8) | static_cast<unsigned char>(bytes[at + i]);
        return v;
    };
    return {word(16), word(20)};
}

}  // namespace

TEST_CASE("render: dualform render writes before and after side by side") {
    const std::filesystem::path dir = scratch_dir("render_cli");
    const std::string png = (dir / "cow.png").string();
    const ProcessResult r =
        run_process(DUALFORM_CLI, {"render", scenario("cow-front-leg-step.json"), "--before-after",
                                   "--width", "200", "--height", "150", "--png", png});
    INFO(r.err);
    REQUIRE(r.exit_code == 0);
    const std::string bytes = read_text(png);
    REQUIRE(bytes.size() > 24);
    CHECK(bytes.substr(1, 3) == "PNG");
    CHECK(png_size(bytes) == std::pair<unsigned, unsigned>(400, 150));
}

TEST_CASE("render: dualform render refuses bad input with exit 2") {
    const std::filesystem::path dir = scratch_dir("render_cli_bad");
    const std::string png = (dir / "x.png").string();
    for (const std::vector<std::string>& args :
         {std::vector<std::string>{"render"},
          {"render", "model:cow"},
          {"render", "model:cow", "--png", png, "--width", "0"},
          {"render", "model:cow", "--png", png, "--samples", "3"},
          {"render", "model:cow", "--png", png, "--camera", "{\"eye\": [0, 0, 0]}"},
          {"render", (dir / "missing.off").string(), "--png", png},
          {"render", "model:cow", scenario("cow-tail-swing.json"), "--png", png},
          {"render", scenario("cow-tail-swing.json"), scenario("triceratops-horn-rotate.json"),
           "--png", png}}) {
        const ProcessResult r = run_process(DUALFORM_CLI, args);
        CHECK(r.exit_code == 2);
        CHECK(r.err.starts_with("error: "));
    }
}

TEST_CASE("render: several scenarios render as successive edits") {
    const std::filesystem::path dir = scratch_dir("render_cli_chain");
    const std::string one = (dir / "leg.png").string(), two = (dir / "leg-tail.png").string();
    for (const auto& [png, inputs] :
         {std::pair{one, std::vector<std::string>{scenario("cow-front-leg-step.json")}},
          std::pair{two, std::vector<std::string>{scenario("cow-front-leg-step.json"),
                                                  scenario("cow-tail-swing.json")}}}) {
        std::vector<std::string> args = {"render"};
        args.insert(args.end(), inputs.begin(), inputs.end());
        args.insert(args.end(), {"--width", "200", "--height", "150", "--png", png});
        const ProcessResult r = run_process(DUALFORM_CLI, args);
        INFO(r.err);
        REQUIRE(r.exit_code == 0);
    }
    CHECK(read_text(one) != read_text(two));
}
