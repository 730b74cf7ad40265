#include <doctest/doctest.h>

#include <png.h>

#include <glm/geometric.hpp>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "mesh/load.hpp"
#include "support/real_models.hpp"
#include "support/run_process.hpp"
#include "support/test_files.hpp"

using namespace dfm;

namespace {

struct Picture {
    std::uint32_t width = 0, height = 0;
    std::vector<std::uint8_t> rgba;
    const std::uint8_t* at(std::uint32_t x, std::uint32_t y) const {
        return &rgba[(std::size_t{y} * width + x) * 4];
    }
};

Picture read_png(const std::string& path) {
    png_image image = {};
    image.version = PNG_IMAGE_VERSION;
    REQUIRE_MESSAGE(png_image_begin_read_from_file(&image, path.c_str()) != 0, path);
    image.format = PNG_FORMAT_RGBA;
    Picture p;
    p.width = image.width;
    p.height = image.height;
    p.rgba.resize(PNG_IMAGE_SIZE(image));
    REQUIRE(png_image_finish_read(&image, nullptr, p.rgba.data(), 0, nullptr) != 0);
    return p;
}

bool is_handle_green(const std::uint8_t* px) {
    return px[1] > 120 && px[0] < 90 && px[2] < 90;
}

bool is_roi_red(const std::uint8_t* px) {
    return px[0] > 120 && px[1] < 90 && px[2] < 90;
}

// ImGui's dark window background over the slate clear colour.
bool is_panel_dark(const std::uint8_t* px) {
    return px[0] < 40 && px[1] < 40 && px[2] < 40;
}

bool is_text_bright(const std::uint8_t* px) {
    return px[0] > 180 && px[1] > 180 && px[2] > 180;
}

// The number after "NAME": in a JSON text (the viewer's scenario writer puts
// one field per line); NaN when absent.
double json_number(const std::string& text, const std::string& name) {
    const std::size_t at = text.find("\"" + name + "\":");
    if (at == std::string::npos) return std::nan("");
    return std::stod(text.substr(at + name.size() + 3));
}

// How many vertices lie more than 1e-6 from the cow's own.
std::size_t moved_vertices(const std::filesystem::path& path, const mesh::Mesh& cow) {
    mesh::Mesh m;
    const Status loaded = mesh::load_mesh(path, m);
    REQUIRE_MESSAGE(loaded.is_ok(), loaded.message());
    REQUIRE(m.vertex_count() == cow.vertex_count());
    std::size_t moved = 0;
    for (std::size_t v = 0; v < m.vertex_count(); ++v) {
        if (glm::length(m.positions[v] - cow.positions[v]) > 1e-6) ++moved;
    }
    return moved;
}

// The viewer's panel: docked at the window's left edge, this wide (panel.hpp).
constexpr std::uint32_t panel_width = 272;

}  // namespace

// The viewer's scripted session under Xvfb: two clicks select the cow's
// leg, a click and a drag move the hoof. Its mesh picture must show the
// deformed leg, and match `dualform render` of the edit it saved, through the
// camera it saved; its window screenshot must show the panel over the same
// picture; and the panel's controls, clicked and typed into through ImGui's
// input, must have done what they say (the validation layer is on; the
// viewer fails on any message).
TEST_CASE(
    "viewer: a scripted leg edit matches the headless render of its scenario, and its panel shows "
    "and works") {
    const std::filesystem::path dir = test::scratch_dir("viewer_script");
    std::ifstream in(DUALFORM_VIEWER_SCRIPT);
    std::stringstream text;
    text << in.rdbuf();
    std::string script = text.str();
    for (std::size_t at = script.find("OUT/"); at != std::string::npos;
         at = script.find("OUT/", at)) {
        script.replace(at, 4, dir.string() + "/");
    }
    const std::string script_path = (dir / "leg.script").string();
    std::ofstream(script_path) << script;

    const test::ProcessResult viewer = test::run_process(
        DUALFORM_XVFB_RUN, {"-a", "-s", "-screen 0 1024x768x24", DUALFORM_VIEWER, "model:cow",
                            "--width", "640", "--height", "480", "--script", script_path});
    INFO(viewer.err);
    REQUIRE(viewer.exit_code == 0);
    MESSAGE(viewer.out);
    CHECK(viewer.out.find("1 handles") != std::string::npos);

    const std::string reference = (dir / "reference.png").string();
    const test::ProcessResult render =
        test::run_process(DUALFORM_CLI, {"render", (dir / "edit.json").string(), "--camera",
                                         (dir / "camera.json").string(), "--png", reference});
    INFO(render.err);
    REQUIRE(render.exit_code == 0);

    const Picture shot = read_png((dir / "mesh.png").string());
    const Picture ref = read_png(reference);
    REQUIRE(shot.width == 640);
    REQUIRE(shot.height == 480);
    REQUIRE(ref.width == shot.width);
    REQUIRE(ref.height == shot.height);

    // The hoof (green) sits where the drag took it: right of where it
    // stood (around x = 366) and at the drag's end (x = 410).
    double green_x = 0.0;
    std::size_t green = 0, red = 0, different = 0;
    for (std::uint32_t y = 0; y < shot.height; ++y) {
        for (std::uint32_t x = 0; x < shot.width; ++x) {
            if (is_handle_green(shot.at(x, y))) green_x += x, ++green;
            if (is_roi_red(shot.at(x, y))) ++red;
            int worst = 0;
            for (int c = 0; c < 3; ++c) {
                worst = std::max(worst, std::abs(int(shot.at(x, y)[c]) - int(ref.at(x, y)[c])));
            }
            if (worst > 24) ++different;
        }
    }
    REQUIRE(green > 20);
    CHECK(red > 200);
    for (int c = 0; c < 3; ++c) CHECK(std::abs(int(shot.at(0, 0)[c]) - int(ref.at(0, 0)[c])) <= 2);
    CHECK(green_x / green > 390.0);
    // The same picture but for the last step of an iterative solve reached
    // along another path (drag frames against one solve): edge pixels only.
    MESSAGE("pixels that differ: " << different);
    CHECK(different < shot.width * shot.height / 200);

    // The window screenshot: the panel on the left, the same mesh picture
    // beside it.
    const Picture window = read_png((dir / "viewer.png").string());
    REQUIRE(window.width == shot.width);
    REQUIRE(window.height == shot.height);
    std::size_t panel_dark = 0, mesh_dark = 0, text_pixels = 0, beside = 0;
    for (std::uint32_t y = 0; y < window.height; ++y) {
        for (std::uint32_t x = 0; x < window.width; ++x) {
            if (x < panel_width) {
                panel_dark += is_panel_dark(window.at(x, y));
                mesh_dark += is_panel_dark(shot.at(x, y));
                text_pixels += is_text_bright(window.at(x, y));
                continue;
            }
            int worst = 0;
            for (int c = 0; c < 3; ++c) {
                worst = std::max(worst, std::abs(int(window.at(x, y)[c]) - int(shot.at(x, y)[c])));
            }
            if (worst > 24) ++beside;
        }
    }
    const std::size_t panel_area = std::size_t{panel_width} * window.height;
    MESSAGE("panel: " << panel_dark << " dark, " << text_pixels << " text pixels; " << beside
                      << " pixels beside it differ");
    CHECK(panel_dark > panel_area / 2);
    CHECK(mesh_dark < panel_area / 100);
    CHECK(text_pixels > 1000);
    CHECK(beside < (window.width - panel_width) * window.height / 200);

    // The tolerance typed into the panel reached the solver settings the
    // edit is saved with.
    CHECK(json_number(test::read_text(dir / "edit.json"), "tolerance") == doctest::Approx(1e-5));
    CHECK(json_number(test::read_text(dir / "edit_tight.json"), "tolerance") ==
          doctest::Approx(1e-7));
    // Bake and Save wrote the edited cow (OFF, and glTF by the path's
    // extension); Undo and Save the cow as it was.
    const mesh::Mesh cow = test::load_real_model("cow").mesh;
    CHECK(moved_vertices(dir / "baked.off", cow) > 50);
    CHECK(moved_vertices(dir / "baked.glb", cow) > 50);
    CHECK(moved_vertices(dir / "undone.off", cow) == 0);
}
