#include <algorithm>
#include <charconv>
#include <chrono>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "dualform/commands.hpp"
#include "dualform/dualform_vulkan.h"
#include "dualform/render_scene.hpp"
#include "dualform/scenario.hpp"
#include "dualform/usage.hpp"
#include "environment/host_environment.hpp"
#include "json/json_writer.hpp"

namespace dfm::cli {

namespace {

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
            return bad_input("unexpected argument '" + std::string(a) + "'\n" + usage(render_help));
        } else {
            o.inputs.emplace_back(a);
        }
    }
    if (o.inputs.empty() || (o.png.empty() && o.bench_frames == 0))
        return bad_input(usage(render_help));
    return 0;
}

// A renderer call's failure: bad input (exit 2) for a refused argument,
// failed work (exit 1) for the device.
int render_failed(dfm_result result) {
    const std::string message = dfm_last_error_message();
    if (result == DFM_ERROR_INVALID_ARGUMENT) return bad_input(message);
    std::fprintf(stderr, "error: render: %s\n", message.c_str());
    return exit_failed;
}

struct RendererDeleter {
    void operator()(dfm_vk_renderer* r) const { dfm_vk_renderer_destroy(r); }
};
using RendererPtr = std::unique_ptr<dfm_vk_renderer, RendererDeleter>;

dfm_vec3_input doubles(const std::vector<glm::dvec3>& p) {
    dfm_vec3_input in = {};
    in.data = p.data();
    in.count = p.size();
    in.type = DFM_SCALAR_FLOAT64;
    return in;
}

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v.empty() ? 0.0 : v[v.size() / 2];
}

double ms_since(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
        .count();
}

// Frame times with the position upload each frame (the positions alternate
// between rest and deformed, so normals are recomputed and every vertex
// streams): pipelined with frames in flight, then each frame waited for and
// read back; and the CPU side of the update alone (copy, normals).
int run_bench(dfm_vk_renderer* renderer, const RenderScene& scene, const dfm_vk_frame& frame,
              int frames) {
    const std::vector<glm::dvec3>& moved =
        scene.deformed.empty() ? scene.rest.positions : scene.deformed;
    const dfm_vec3_input poses[2] = {doubles(scene.rest.positions), doubles(moved)};
    std::vector<std::uint8_t> rgba(std::size_t{frame.camera.width} * frame.camera.height * 4);
    std::vector<double> pipelined, read_back, update;
    for (int pass = 0; pass < 2; ++pass) {
        std::vector<double>& times = pass == 0 ? pipelined : read_back;
        std::uint8_t* out = pass == 0 ? nullptr : rgba.data();
        const std::size_t out_size = pass == 0 ? 0 : rgba.size();
        for (int f = 0; f < frames; ++f) {
            const auto start = std::chrono::steady_clock::now();
            if (dfm_result r = dfm_vk_renderer_update_positions(renderer, &poses[f % 2]);
                r != DFM_OK) {
                return render_failed(r);
            }
            update.push_back(ms_since(start));
            if (dfm_result r = dfm_vk_renderer_render_offscreen(renderer, &frame, out, out_size);
                r != DFM_OK) {
                return render_failed(r);
            }
            times.push_back(ms_since(start));
        }
    }
    std::uint32_t samples = 0;
    if (dfm_result r = dfm_vk_renderer_sample_count(renderer, &samples); r != DFM_OK) {
        return render_failed(r);
    }
    json::JsonWriter json;
    json.begin_object();
    json.field("vertices", scene.rest.vertex_count());
    json.field("faces", scene.rest.indices.size() / 3);
    json.field("width", frame.camera.width);
    json.field("height", frame.camera.height);
    json.field("samples", samples);
    json.field("frames", frames);
    json.field("median_frame_ms", median(pipelined));
    json.field("median_frame_readback_ms", median(read_back));
    json.field("median_position_update_ms", median(update));
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

int draw(dfm_vk_renderer* renderer, const dfm_vk_frame& frame, std::vector<std::uint8_t>& rgba) {
    rgba.assign(std::size_t{frame.camera.width} * frame.camera.height * 4, 0);
    if (dfm_result r = dfm_vk_renderer_render_offscreen(renderer, &frame, rgba.data(), rgba.size());
        r != DFM_OK) {
        return render_failed(r);
    }
    return exit_ok;
}

}  // namespace

int run_render(std::span<const std::string_view> args) {
    RenderOptions o;
    if (int code = parse(args, o); code != 0) return code;

    RenderScene scene;
    if (ToolStatus s = load_render_scene(o.inputs, scene); !s) return bad_input(s.message());

    dfm_vk_frame frame = {};
    frame.flags = (o.wireframe ? DFM_VK_FLAG_WIREFRAME : 0u) | (o.flat ? DFM_VK_FLAG_FLAT : 0u);
    if (!o.camera.empty()) {
        if (ToolStatus s = read_camera_argument(o.camera, frame.camera); !s) {
            return bad_input(s.message());
        }
        if (o.width) frame.camera.width = o.width;
        if (o.height) frame.camera.height = o.height;
    } else {
        std::vector<glm::dvec3> everything = scene.rest.positions;
        everything.insert(everything.end(), scene.deformed.begin(), scene.deformed.end());
        const dfm_vec3_input all = doubles(everything);
        if (dfm_result r = dfm_vk_framing_camera(&all, o.width ? o.width : 800,
                                                 o.height ? o.height : 600, &frame.camera);
            r != DFM_OK) {
            return render_failed(r);
        }
    }

    dfm_vk_renderer_desc desc = {};
    desc.max_samples = o.samples;
    desc.validation = tools::validation_from_environment();
    dfm_vk_renderer* created = nullptr;
    if (dfm_result r = dfm_vk_renderer_create_headless(&desc, &created); r != DFM_OK) {
        return render_failed(r);
    }
    const RendererPtr renderer(created);
    const dfm_vec3_input rest = doubles(scene.rest.positions);
    if (dfm_result r = dfm_vk_renderer_set_mesh(renderer.get(), &rest, scene.rest.indices.data(),
                                                scene.rest.indices.size() / 3);
        r != DFM_OK) {
        return render_failed(r);
    }
    if (!scene.marks.empty()) {
        if (dfm_result r =
                dfm_vk_renderer_set_marks(renderer.get(), scene.marks.data(), scene.marks.size());
            r != DFM_OK) {
            return render_failed(r);
        }
    }

    int code = exit_ok;
    if (o.bench_frames > 0) code = run_bench(renderer.get(), scene, frame, o.bench_frames);
    if (code == exit_ok && !o.png.empty()) {
        const std::uint32_t w = frame.camera.width;
        const std::uint32_t h = frame.camera.height;
        std::vector<std::uint8_t> picture;
        std::vector<std::uint8_t> rest_picture;
        if (o.before_after) {
            if (dfm_result r = dfm_vk_renderer_update_positions(renderer.get(), &rest);
                r != DFM_OK) {
                return render_failed(r);
            }
            if (int c = draw(renderer.get(), frame, rest_picture); c != exit_ok) return c;
        }
        if (!scene.deformed.empty()) {
            const dfm_vec3_input deformed = doubles(scene.deformed);
            if (dfm_result r = dfm_vk_renderer_update_positions(renderer.get(), &deformed);
                r != DFM_OK) {
                return render_failed(r);
            }
        }
        if (int c = draw(renderer.get(), frame, picture); c != exit_ok) return c;
        if (o.before_after) {
            std::vector<std::uint8_t> both(picture.size() * 2);
            place(both, rest_picture, w, h, 0);
            place(both, picture, w, h, w);
            picture = std::move(both);
        }
        if (dfm_result r = dfm_vk_write_png(o.png.c_str(), picture.data(), picture.size(),
                                            o.before_after ? 2 * w : w, h);
            r != DFM_OK) {
            return render_failed(r);
        }
    }
    std::uint64_t messages = 0;
    if (dfm_result r = dfm_vk_renderer_validation_message_count(renderer.get(), &messages);
        r != DFM_OK) {
        return render_failed(r);
    }
    if (messages > 0) {
        std::fprintf(stderr, "error: render: %llu Vulkan validation messages (see above)\n",
                     static_cast<unsigned long long>(messages));
        return exit_failed;
    }
    return code;
}

}  // namespace dfm::cli
