#include <algorithm>
#include <charconv>
#include <chrono>
#include <cstdio>
#include <optional>
#include <string>
#include <vector>

#include <glm/vec2.hpp>

#include "dualform/c_api.hpp"
#include "dualform/commands.hpp"
#include "dualform/scenario.hpp"
#include "dualform/usage.hpp"
#include "json/json_writer.hpp"

namespace dfm::cli {

namespace {

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

std::string hit_json(const dfm_hit& hit) {
    json::JsonWriter j;
    j.begin_object().field("hit", hit.hit);
    if (hit.hit) {
        j.field("face", hit.face);
        j.field("vertex", hit.vertex);
        j.key("point").numbers(hit.point, 3);
        j.field("distance", hit.distance);
        j.key("barycentric").numbers(hit.barycentric, 3);
    }
    j.end_object();
    return j.str();
}

// Times `rays` picks spread over a 3×3 pixel neighbourhood of `pixel`, so
// the rays are realistic clicks rather than one cached ray; prints the
// median and 90th percentile per ray in microseconds.
int bench(dfm_mesh* mesh, const dfm_camera& camera, glm::dvec2 pixel, std::size_t rays) {
    std::vector<double> us(rays);
    std::size_t hits = 0;
    for (std::size_t i = 0; i < rays; ++i) {
        const glm::dvec2 p = pixel + glm::dvec2(static_cast<double>(i % 3) - 1.0,
                                                static_cast<double>(i / 3 % 3) - 1.0);
        dfm_hit hit = {};
        const auto start = std::chrono::steady_clock::now();
        const dfm_result r = dfm_mesh_pick(mesh, &camera, p.x, p.y, &hit);
        us[i] = std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - start)
                    .count();
        if (ToolStatus s = api_status(r); !s) return bad_input(s.message());
        hits += hit.hit;
    }
    std::sort(us.begin(), us.end());
    json::JsonWriter j;
    j.begin_object();
    j.field("rays", rays).field("hits", hits);
    j.field("median_us", us[rays / 2]).field("p90_us", us[rays * 9 / 10]);
    j.end_object();
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
            return bad_input(std::string("unexpected argument '") + std::string(a) + "'\n" +
                             usage(pick_help));
        } else {
            mesh_spec = std::string(a);
        }
    }
    if (mesh_spec.empty() || camera_text.empty() || !pixel) return bad_input(usage(pick_help));

    dfm_camera camera{};
    if (ToolStatus s = read_camera_argument(camera_text, camera); !s) return bad_input(s.message());
    if (pixel->x < 0.0 || pixel->y < 0.0 || pixel->x > camera.width || pixel->y > camera.height) {
        return bad_input("--pixel: the pixel lies outside the " + std::to_string(camera.width) +
                         "x" + std::to_string(camera.height) + " image");
    }
    ContextPtr context;
    if (ToolStatus s = create_context(context); !s) return bad_input(s.message());
    dfm_mesh* loaded = nullptr;
    if (ToolStatus s = api_status(dfm_mesh_load(context.get(), mesh_spec.c_str(), &loaded)); !s) {
        return bad_input(s.message());
    }
    const MeshPtr mesh(loaded);
    if (bench_rays > 0) return bench(mesh.get(), camera, *pixel, bench_rays);
    dfm_hit hit = {};
    if (ToolStatus s = api_status(dfm_mesh_pick(mesh.get(), &camera, pixel->x, pixel->y, &hit));
        !s) {
        return bad_input(s.message());
    }
    std::printf("%s\n", hit_json(hit).c_str());
    return exit_ok;
}

}  // namespace dfm::cli
