#include <algorithm>
#include <charconv>
#include <chrono>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "dualform/commands.hpp"
#include "dualform/pick_camera.hpp"
#include "dualform/render_scene.hpp"
#include "dualform/scenario.hpp"
#include "environment/host_environment.hpp"
#include "json/json_writer.hpp"
#include "render/png_writer.hpp"
#include "render/renderer.hpp"
#include "render/view_transform.hpp"

namespace dfm::cli {

namespace {

constexpr const char* usage =
    "usage: dualform render (SCENARIO...|MESH) --png OUT [--camera JSON] [--width W --height H]\n"
    "       [--before-after] [--wireframe] [--flat] [--samples 1|2|4] [--bench N]\n"
    "       (several scenarios: successive edits of one mesh, each baked before the next)";

struct RenderOptions {
    std::vector<std::string> inputs;
    std::string png;
    std::string camera;
    std::uint32_t width = 0, height = 0;
    bool before_after = false;
    bool wireframe = false;
    bool flat = false;
    std::uint32_t samples = 4;
    int bench_frames = 0;
};

bool parse_count(std::string_view text, std::uint32_t low, std::uint32_t high, std::uint32_t& out) {
    const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), out);
    return ec == std::errc() && end == text.data() + text.size() && out >= low && out <= high;
}

// Returns 0 when parsed, or the exit code of the error already printed.
int parse(std::span<const std::string_view> args, RenderOptions& o) {
    for (std::size_t i = 0; i < args.size(); ++i) {
        const std::string_view a = args[i];
        const bool has_value = i + 1 < args.size();
        if (a == "--png" || a == "--camera") {
            if (!has_value) return bad_input(std::string(a) + " needs a value");
            (a == "--png" ? o.png : o.camera) = std::string(args[++i]);
        } else if (a == "--width" || a == "--height") {
            std::uint32_t value = 0;
            if (!has_value || !parse_count(args[++i], 1, 8192, value)) {
                return bad_input(std::string(a) + " needs a whole number from 1 to 8192");
            }
            (a == "--width" ? o.width : o.height) = value;
        } else if (a == "--bench") {
            std::uint32_t frames = 0;
            if (!has_value || !parse_count(args[++i], 1, 100000, frames)) {
                return bad_input("--bench needs a frame count from 1 to 100000");
            }
            o.bench_frames = static_cast<int>(frames);
        } else if (a == "--samples") {
            if (!has_value || !parse_count(args[++i], 1, 4, o.samples) || o.samples == 3) {
                return bad_input("--samples needs 1, 2 or 4");
            }
        } else if (a == "--before-after") {
            o.before_after = true;
        } else if (a == "--wireframe") {
            o.wireframe = true;
        } else if (a == "--flat") {
            o.flat = true;
        } else if (a.starts_with("--")) {
            return bad_input("unexpected argument '" + std::string(a) + "'\n" + usage);
        } else {
            o.inputs.emplace_back(a);
        }
    }
    if (o.inputs.empty() || (o.png.empty() && o.bench_frames == 0)) return bad_input(usage);
    return 0;
}

int render_failed(const render::RenderStatus& s) {
    if (s.fault() == render::Fault::invalid_argument) return bad_input(s.message());
    std::fprintf(stderr, "error: render: %s\n", s.message().c_str());
    return exit_failed;
}

render::StridedPositions strided(const std::vector<glm::dvec3>& p) {
    return render::StridedPositions{p.data(), p.size(), sizeof(glm::dvec3), true};
}

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v.empty() ? 0.0 : v[v.size() / 2];
}

// Frame times with the position upload each frame (the positions alternate
// between rest and deformed, so normals are recomputed and every vertex
// streams): pipelined with frames in flight, then each frame waited for and
// read back; and the CPU side of the update alone (copy, normals).
int run_bench(render::Renderer& renderer, const RenderScene& scene,
              const render::ViewSettings& view, int frames) {
    const std::vector<glm::dvec3>& moved =
        scene.deformed.empty() ? scene.rest.positions : scene.deformed;
    std::vector<std::uint8_t> rgba(std::size_t{view.camera.width} * view.camera.height * 4);
    std::vector<double> pipelined, read_back, update;
    for (int pass = 0; pass < 2; ++pass) {
        std::vector<double>& times = pass == 0 ? pipelined : read_back;
        const std::span<std::uint8_t> out = pass == 0 ? std::span<std::uint8_t>() : rgba;
        for (int f = 0; f < frames; ++f) {
            const auto start = std::chrono::steady_clock::now();
            const std::vector<glm::dvec3>& p = (f % 2) ? moved : scene.rest.positions;
            if (auto s = renderer.set_positions(strided(p)); !s) return render_failed(s);
            update.push_back(
                std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
                    .count());
            if (auto s = renderer.render_offscreen(view, out); !s) return render_failed(s);
            times.push_back(
                std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
                    .count());
        }
    }
    json::JsonWriter json;
    json.begin_object();
    json.key("vertices").value(std::uint64_t{scene.rest.vertex_count()});
    json.key("faces").value(std::uint64_t{scene.rest.face_count()});
    json.key("width").value(std::uint64_t{view.camera.width});
    json.key("height").value(std::uint64_t{view.camera.height});
    json.key("samples").value(std::uint64_t(renderer.samples()));
    json.key("frames").value(std::uint64_t(frames));
    json.key("median_frame_ms").value(median(pipelined));
    json.key("median_frame_readback_ms").value(median(read_back));
    json.key("median_position_update_ms").value(median(update));
    json.end_object();
    std::printf("%s\n", json.str().c_str());
    return exit_ok;
}

// Side by side: the left half of `out` gets `left`, the right half `right`.
void place(std::vector<std::uint8_t>& out, const std::vector<std::uint8_t>& picture,
           std::uint32_t width, std::uint32_t height, std::uint32_t column) {
    for (std::uint32_t y = 0; y < height; ++y) {
        std::copy_n(&picture[std::size_t{y} * width * 4], std::size_t{width} * 4,
                    &out[(std::size_t{y} * 2 * width + column) * 4]);
    }
}

}  // namespace

int run_render(std::span<const std::string_view> args) {
    RenderOptions o;
    if (int code = parse(args, o); code != 0) return code;

    RenderScene scene;
    if (Status s = load_render_scene(o.inputs, scene); !s) return bad_input(s.message());

    render::ViewSettings view;
    view.wireframe = o.wireframe;
    view.flat = o.flat;
    if (!o.camera.empty()) {
        dfm_camera camera{};
        if (Status s = read_camera_argument(o.camera, camera); !s) return bad_input(s.message());
        view.camera = to_pick_camera(camera);
        if (o.width) view.camera.width = o.width;
        if (o.height) view.camera.height = o.height;
        if (Status s = pick::check_camera(view.camera); !s) return bad_input(s.message());
    } else {
        std::vector<glm::dvec3> everything = scene.rest.positions;
        everything.insert(everything.end(), scene.deformed.begin(), scene.deformed.end());
        view.camera =
            render::framing_camera(everything, o.width ? o.width : 800, o.height ? o.height : 600);
    }

    render::OwnDeviceOptions options;
    options.validation = tools::validation_from_environment();
    options.max_samples = static_cast<VkSampleCountFlagBits>(o.samples);
    std::unique_ptr<render::Renderer> renderer;
    if (auto s = render::Renderer::create_headless(options, renderer); !s) {
        return render_failed(s);
    }
    std::vector<std::uint32_t> indices;
    for (const mesh::Triangle& t : scene.rest.triangles)
        indices.insert(indices.end(), t.begin(), t.end());
    if (auto s = renderer->set_mesh(strided(scene.rest.positions), indices); !s) {
        return render_failed(s);
    }
    if (!scene.marks.empty()) {
        if (auto s = renderer->set_marks(scene.marks); !s) return render_failed(s);
    }

    int code = exit_ok;
    if (o.bench_frames > 0) {
        code = run_bench(*renderer, scene, view, o.bench_frames);
    }
    if (code == exit_ok && !o.png.empty()) {
        const std::uint32_t w = view.camera.width;
        const std::uint32_t h = view.camera.height;
        std::vector<std::uint8_t> picture(std::size_t{w} * h * 4);
        std::vector<std::uint8_t> rest_picture;
        if (o.before_after) {
            if (auto s = renderer->set_positions(strided(scene.rest.positions)); !s) {
                return render_failed(s);
            }
            rest_picture.resize(picture.size());
            if (auto s = renderer->render_offscreen(view, rest_picture); !s) {
                return render_failed(s);
            }
        }
        if (!scene.deformed.empty()) {
            if (auto s = renderer->set_positions(strided(scene.deformed)); !s) {
                return render_failed(s);
            }
        }
        if (auto s = renderer->render_offscreen(view, picture); !s) return render_failed(s);
        if (o.before_after) {
            std::vector<std::uint8_t> both(picture.size() * 2);
            place(both, rest_picture, w, h, 0);
            place(both, picture, w, h, w);
            picture = std::move(both);
        }
        if (auto s = render::write_png(o.png, picture, o.before_after ? 2 * w : w, h); !s) {
            return render_failed(s);
        }
    }
    if (const std::uint64_t messages = renderer->validation_messages(); messages > 0) {
        std::fprintf(stderr, "error: render: %llu Vulkan validation messages (see above)\n",
                     static_cast<unsigned long long>(messages));
        return exit_failed;
    }
    return code;
}

}  // namespace dfm::cli
