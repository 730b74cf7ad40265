#include <algorithm>
#include <charconv>
#include <chrono>
#include <cstdio>
#include <optional>
#include <string>
#include <vector>

#include "dualform/commands.hpp"
#include "dualform/mesh_input.hpp"
#include "dualform/pick_camera.hpp"
#include "json/json_writer.hpp"
#include "pick/pick.hpp"

namespace dfm::cli {

namespace {

constexpr const char* usage =
    "usage: dualform pick MESH --camera JSON --pixel X,Y [--bench N]\n"
    "       JSON: a camera object inline (starting with '{') or a file holding one";

bool parse_number(std::string_view text, double& out) {
    const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), out);
    return ec == std::errc() && end == text.data() + text.size();
}

bool parse_pixel(std::string_view text, glm::dvec2& out) {
    const std::size_t comma = text.find(',');
    if (comma == std::string_view::npos) return false;
    return parse_number(text.substr(0, comma), out.x) &&
           parse_number(text.substr(comma + 1), out.y);
}

std::string hit_json(const std::optional<pick::Hit>& hit) {
    json::JsonWriter j;
    j.begin_object().key("hit").value(hit.has_value());
    if (hit) {
        j.key("face").value(std::uint64_t{hit->face});
        j.key("vertex").value(std::uint64_t{hit->vertex});
        j.key("point").begin_array();
        for (int k = 0; k < 3; ++k) j.value(hit->point[k]);
        j.end_array();
        j.key("distance").value(hit->distance);
        j.key("barycentric").begin_array().value(hit->u).value(hit->v).value(hit->w).end_array();
    }
    j.end_object();
    return j.str();
}

// Times `rays` picks spread over a 3×3 pixel neighbourhood of `pixel`, so
// the rays are realistic clicks rather than one cached ray; prints the
// median and 90th percentile per ray in microseconds.
int bench(const pick::EmbreeScene& scene, const pick::Camera& camera, glm::dvec2 pixel,
          std::size_t rays) {
    std::vector<double> us(rays);
    std::optional<pick::Hit> hit;
    std::size_t hits = 0;
    for (std::size_t i = 0; i < rays; ++i) {
        const glm::dvec2 p = pixel + glm::dvec2(static_cast<double>(i % 3) - 1.0,
                                                static_cast<double>(i / 3 % 3) - 1.0);
        const auto start = std::chrono::steady_clock::now();
        const Status s = pick::pick_pixel(scene, camera, p, hit);
        us[i] = std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - start)
                    .count();
        if (!s) return bad_input(s.message());
        hits += hit.has_value();
    }
    std::sort(us.begin(), us.end());
    json::JsonWriter j;
    j.begin_object()
        .key("rays")
        .value(std::uint64_t{rays})
        .key("hits")
        .value(std::uint64_t{hits})
        .key("median_us")
        .value(us[rays / 2])
        .key("p90_us")
        .value(us[rays * 9 / 10])
        .end_object();
    std::printf("%s\n", j.str().c_str());
    return exit_ok;
}

}  // namespace

int run_pick(std::span<const std::string_view> args) {
    std::string mesh_spec, camera_text;
    std::optional<glm::dvec2> pixel;
    std::size_t bench_rays = 0;
    for (std::size_t i = 0; i < args.size(); ++i) {
        const std::string_view a = args[i];
        const bool has_value = i + 1 < args.size();
        if (a == "--camera") {
            if (!has_value) return bad_input("--camera needs a JSON object or a file");
            camera_text = std::string(args[++i]);
        } else if (a == "--pixel") {
            glm::dvec2 p;
            if (!has_value || !parse_pixel(args[++i], p)) {
                return bad_input("--pixel: expected X,Y (two numbers, e.g. 320,240)");
            }
            pixel = p;
        } else if (a == "--bench") {
            double n = 0.0;
            if (!has_value || !parse_number(args[++i], n) || !(n >= 1.0 && n <= 1e8)) {
                return bad_input("--bench: expected a ray count from 1 to 100000000");
            }
            bench_rays = static_cast<std::size_t>(n);
        } else if (a.starts_with("--") || !mesh_spec.empty()) {
            return bad_input(std::string("unexpected argument '") + std::string(a) + "'\n" + usage);
        } else {
            mesh_spec = std::string(a);
        }
    }
    if (mesh_spec.empty() || camera_text.empty() || !pixel) return bad_input(usage);

    dfm_camera scenario_camera{};
    if (Status s = read_camera_argument(camera_text, scenario_camera); !s) {
        return bad_input(s.message());
    }
    const pick::Camera camera = to_pick_camera(scenario_camera);
    if (pixel->x < 0.0 || pixel->y < 0.0 || pixel->x > camera.width || pixel->y > camera.height) {
        return bad_input("--pixel: the pixel lies outside the " + std::to_string(camera.width) +
                         "x" + std::to_string(camera.height) + " image");
    }
    mesh::Mesh mesh;
    mesh::LoadReport report;
    if (Status s = load_mesh_input(mesh_spec, mesh, report); !s) return bad_input(s.message());
    pick::EmbreeScene scene;
    if (Status s = pick::EmbreeScene::create(mesh.positions, mesh.triangles, scene); !s) {
        return bad_input(mesh_spec + ": " + s.message());
    }
    if (bench_rays > 0) return bench(scene, camera, *pixel, bench_rays);
    std::optional<pick::Hit> hit;
    if (Status s = pick::pick_pixel(scene, camera, *pixel, hit); !s) return bad_input(s.message());
    std::printf("%s\n", hit_json(hit).c_str());
    return exit_ok;
}

}  // namespace dfm::cli
