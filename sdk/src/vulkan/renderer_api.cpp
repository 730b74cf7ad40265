#include <algorithm>
#include <cstdint>
#include <cstring>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "c_boundary.hpp"
#include "camera_convert.hpp"
#include "descriptor_layouts_vulkan.hpp"
#include "dualform/dualform_vulkan.h"
#include "render/png_writer.hpp"
#include "render/renderer.hpp"
#include "render/validation.hpp"
#include "render/view_transform.hpp"
#include "vec3_arrays.hpp"

// A handle carries a tag, so a destroyed or foreign pointer is caught where
// the memory still holds it.
struct dfm_vk_renderer {
    static constexpr std::uint64_t live_tag = 0x6466'6d5f'766b'7231ULL;
    std::uint64_t tag = live_tag;
    std::unique_ptr<dfm::render::Renderer> impl;
    // What the host's overlay function returned in the present running now.
    dfm_result overlay_result = DFM_OK;
};

namespace {

using dfm::sdk::fail;
using dfm::sdk::guarded;
using dfm::sdk::report;
namespace render = dfm::render;

bool live(const dfm_vk_renderer* r) {
    return r != nullptr && r->tag == dfm_vk_renderer::live_tag && r->impl;
}

dfm_result bad_handle(const char* function) {
    return report(function, DFM_ERROR_INVALID_HANDLE, "renderer is NULL or destroyed");
}

render::StridedPositions to_strided(const dfm_vec3_input& p) {
    return render::StridedPositions{p.data, p.count, p.stride, p.type == DFM_SCALAR_FLOAT64};
}

dfm_result check_scalar(const char* function, const dfm_vec3_input& p) {
    if (!dfm::sdk::known_scalar_type(p.type)) {
        return report(function, DFM_ERROR_INVALID_ARGUMENT,
                      "positions.type must be DFM_SCALAR_FLOAT64 or DFM_SCALAR_FLOAT32");
    }
    return DFM_OK;
}

render::OwnDeviceOptions own_options(const char* function, const dfm_vk_renderer_desc* desc,
                                     dfm_result& result) {
    render::OwnDeviceOptions options;
    result = DFM_OK;
    if (desc == nullptr) return options;
    options.validation = desc->validation;
    if (desc->frames_in_flight != 0) options.frames_in_flight = desc->frames_in_flight;
    switch (desc->max_samples) {
        case 0:
        case 4: options.max_samples = VK_SAMPLE_COUNT_4_BIT; break;
        case 2: options.max_samples = VK_SAMPLE_COUNT_2_BIT; break;
        case 1: options.max_samples = VK_SAMPLE_COUNT_1_BIT; break;
        default:
            result =
                report(function, DFM_ERROR_INVALID_ARGUMENT, "max_samples must be 0, 1, 2 or 4");
    }
    options.vsync = !desc->no_vsync;
    return options;
}

// The frame as the renderer takes it; the camera's size is `extent` when
// given (window and host paths), the camera's own otherwise.
dfm_result to_view(const char* function, const dfm_vk_frame* frame, std::uint32_t width,
                   std::uint32_t height, render::ViewSettings& view) {
    if (frame == nullptr) return report(function, DFM_ERROR_INVALID_ARGUMENT, "frame is NULL");
    if (frame->flags & ~(DFM_VK_FLAG_WIREFRAME | DFM_VK_FLAG_FLAT)) {
        return report(function, DFM_ERROR_INVALID_ARGUMENT, "frame.flags has unknown bits");
    }
    view.camera = dfm::sdk::to_camera(frame->camera);
    if (width != 0) view.camera.width = width;
    if (height != 0) view.camera.height = height;
    if (dfm::Status s = dfm::pick::check_camera(view.camera); !s) {
        return report(function, DFM_ERROR_INVALID_ARGUMENT, s.message());
    }
    view.wireframe = (frame->flags & DFM_VK_FLAG_WIREFRAME) != 0;
    view.flat = (frame->flags & DFM_VK_FLAG_FLAT) != 0;
    const float* bg = frame->background;
    if (bg[0] != 0.0f || bg[1] != 0.0f || bg[2] != 0.0f || bg[3] != 0.0f) {
        view.background = {bg[0], bg[1], bg[2], bg[3]};
    }
    return DFM_OK;
}

// Both present calls: the frame, the overlay's own result over the renderer's.
dfm_result present_frame(const char* fn, dfm_vk_renderer* renderer, const dfm_vk_frame* frame,
                         std::span<std::uint8_t> rgba, bool* presented) {
    if (presented != nullptr) *presented = false;
    if (!live(renderer)) return bad_handle(fn);
    render::ViewSettings view;
    // The real size comes from the window; 1x1 only lets the camera check pass.
    if (dfm_result r = to_view(fn, frame, 1, 1, view); r != DFM_OK) return r;
    bool shown = false;
    renderer->overlay_result = DFM_OK;
    if (dfm::Status s = renderer->impl->present(view, shown, rgba); !s) {
        return report(fn, s);
    }
    if (presented != nullptr) *presented = shown;
    if (renderer->overlay_result != DFM_OK) {
        return report(fn, renderer->overlay_result,
                      std::string("the overlay's record function returned ") +
                          dfm_result_name(renderer->overlay_result));
    }
    return DFM_OK;
}

dfm_result wrap(std::unique_ptr<render::Renderer> impl, dfm_vk_renderer** out) {
    auto handle = std::make_unique<dfm_vk_renderer>();
    handle->impl = std::move(impl);
    *out = handle.release();
    return DFM_OK;
}

}  // namespace

extern "C" {

DFM_API dfm_result dfm_vk_renderer_create_headless(const dfm_vk_renderer_desc* desc,
                                                   dfm_vk_renderer** out) {
    const char* fn = "dfm_vk_renderer_create_headless";
    return guarded(fn, [&]() -> dfm_result {
        if (out == nullptr) return report(fn, DFM_ERROR_INVALID_ARGUMENT, "out is NULL");
        *out = nullptr;
        dfm_result checked = DFM_OK;
        const render::OwnDeviceOptions options = own_options(fn, desc, checked);
        if (checked != DFM_OK) return checked;
        std::unique_ptr<render::Renderer> impl;
        if (dfm::Status s = render::Renderer::create_headless(options, impl); !s) {
            return report(fn, s);
        }
        return wrap(std::move(impl), out);
    });
}

DFM_API dfm_result dfm_vk_renderer_create_for_window(const dfm_vk_renderer_desc* desc,
                                                     const dfm_vk_window* window,
                                                     dfm_vk_renderer** out) {
    const char* fn = "dfm_vk_renderer_create_for_window";
    return guarded(fn, [&]() -> dfm_result {
        if (out == nullptr) return report(fn, DFM_ERROR_INVALID_ARGUMENT, "out is NULL");
        *out = nullptr;
        if (window == nullptr) return report(fn, DFM_ERROR_INVALID_ARGUMENT, "window is NULL");
        if (window->create_surface == nullptr || window->framebuffer_size == nullptr) {
            return report(fn, DFM_ERROR_INVALID_ARGUMENT,
                          "window: create_surface and framebuffer_size are required");
        }
        if (window->instance_extension_count > 0 && window->instance_extensions == nullptr) {
            return report(fn, DFM_ERROR_INVALID_ARGUMENT,
                          "window: instance_extensions is NULL but its count is not 0");
        }
        dfm_result checked = DFM_OK;
        const render::OwnDeviceOptions options = own_options(fn, desc, checked);
        if (checked != DFM_OK) return checked;
        const dfm_vk_window w = *window;
        render::WindowSurface surface;
        surface.instance_extensions.assign(w.instance_extensions,
                                           w.instance_extensions + w.instance_extension_count);
        surface.create_surface = [w](VkInstance instance, VkSurfaceKHR* out_surface) {
            return w.create_surface(w.user, instance, out_surface);
        };
        surface.framebuffer_extent = [w] {
            std::uint32_t width = 0;
            std::uint32_t height = 0;
            w.framebuffer_size(w.user, &width, &height);
            return VkExtent2D{width, height};
        };
        std::unique_ptr<render::Renderer> impl;
        if (dfm::Status s = render::Renderer::create_window(options, std::move(surface), impl);
            !s) {
            return report(fn, s);
        }
        return wrap(std::move(impl), out);
    });
}

DFM_API dfm_result dfm_vk_renderer_create_host(const dfm_vk_host_desc* desc,
                                               dfm_vk_renderer** out) {
    const char* fn = "dfm_vk_renderer_create_host";
    return guarded(fn, [&]() -> dfm_result {
        if (out == nullptr) return report(fn, DFM_ERROR_INVALID_ARGUMENT, "out is NULL");
        *out = nullptr;
        if (desc == nullptr) return report(fn, DFM_ERROR_INVALID_ARGUMENT, "desc is NULL");
        if (desc->samples != 0 && desc->samples != VK_SAMPLE_COUNT_1_BIT &&
            desc->samples != VK_SAMPLE_COUNT_2_BIT && desc->samples != VK_SAMPLE_COUNT_4_BIT &&
            desc->samples != VK_SAMPLE_COUNT_8_BIT) {
            return report(fn, DFM_ERROR_INVALID_ARGUMENT, "samples must be 0, 1, 2, 4 or 8");
        }
        render::HostDevice host;
        host.gpu.instance = desc->instance;
        host.gpu.physical = desc->physical_device;
        host.gpu.device = desc->device;
        host.gpu.queue_family = desc->queue_family;
        host.gpu.queue = desc->queue;
        host.gpu.wireframe = desc->fill_mode_non_solid;
        host.formats.color = desc->color_format;
        host.formats.depth = desc->depth_format;
        host.formats.samples = desc->samples == 0 ? VK_SAMPLE_COUNT_1_BIT : desc->samples;
        if (desc->frames_in_flight != 0) host.frames_in_flight = desc->frames_in_flight;
        std::unique_ptr<render::Renderer> impl;
        if (dfm::Status s = render::Renderer::create_host(host, impl); !s) {
            return report(fn, s);
        }
        return wrap(std::move(impl), out);
    });
}

DFM_API void dfm_vk_renderer_destroy(dfm_vk_renderer* renderer) {
    if (!live(renderer)) return;
    renderer->tag = 0;
    delete renderer;
}

DFM_API dfm_result dfm_vk_renderer_set_mesh(dfm_vk_renderer* renderer,
                                            const dfm_vec3_input* positions,
                                            const uint32_t* triangle_indices,
                                            size_t triangle_count) {
    const char* fn = "dfm_vk_renderer_set_mesh";
    return guarded(fn, [&]() -> dfm_result {
        if (!live(renderer)) return bad_handle(fn);
        if (positions == nullptr || triangle_indices == nullptr) {
            return report(fn, DFM_ERROR_INVALID_ARGUMENT, "positions or indices are NULL");
        }
        if (dfm_result r = check_scalar(fn, *positions); r != DFM_OK) return r;
        if (triangle_count > SIZE_MAX / 3) {
            return report(fn, DFM_ERROR_INVALID_ARGUMENT, "triangle_count is too large");
        }
        return report(fn, renderer->impl->set_mesh(to_strided(*positions),
                                                   {triangle_indices, triangle_count * 3}));
    });
}

DFM_API dfm_result dfm_vk_renderer_update_positions(dfm_vk_renderer* renderer,
                                                    const dfm_vec3_input* positions) {
    const char* fn = "dfm_vk_renderer_update_positions";
    return guarded(fn, [&]() -> dfm_result {
        if (!live(renderer)) return bad_handle(fn);
        if (positions == nullptr)
            return report(fn, DFM_ERROR_INVALID_ARGUMENT, "positions is NULL");
        if (dfm_result r = check_scalar(fn, *positions); r != DFM_OK) return r;
        return report(fn, renderer->impl->set_positions(to_strided(*positions)));
    });
}

DFM_API dfm_result dfm_vk_renderer_set_marks(dfm_vk_renderer* renderer, const uint8_t* marks,
                                             size_t count) {
    const char* fn = "dfm_vk_renderer_set_marks";
    return guarded(fn, [&]() -> dfm_result {
        if (!live(renderer)) return bad_handle(fn);
        if (marks == nullptr && count != 0) {
            return report(fn, DFM_ERROR_INVALID_ARGUMENT, "marks is NULL but count is not 0");
        }
        return report(
            fn, renderer->impl->set_marks({marks, marks == nullptr ? std::size_t{0} : count}));
    });
}

DFM_API dfm_result dfm_vk_renderer_set_lines(dfm_vk_renderer* renderer,
                                             const dfm_vk_polyline* lines, size_t count) {
    const char* fn = "dfm_vk_renderer_set_lines";
    return guarded(fn, [&]() -> dfm_result {
        if (!live(renderer)) return bad_handle(fn);
        if (lines == nullptr && count != 0) {
            return report(fn, DFM_ERROR_INVALID_ARGUMENT, "lines is NULL but count is not 0");
        }
        std::vector<render::Polyline> polylines(count);
        for (std::size_t i = 0; i < count; ++i) {
            const dfm_vk_polyline& in = lines[i];
            if (dfm_result r = check_scalar(fn, in.points); r != DFM_OK) return r;
            if (in.points.count > 0 && in.points.data == nullptr) {
                return report(fn, DFM_ERROR_INVALID_ARGUMENT,
                              "lines[" + std::to_string(i) + "].points.data is NULL");
            }
            const render::StridedPositions points = to_strided(in.points);
            const std::size_t triple = points.is_double ? 3 * sizeof(double) : 3 * sizeof(float);
            if (points.stride != 0 && points.stride < triple) {
                return report(fn, DFM_ERROR_INVALID_ARGUMENT,
                              "lines[" + std::to_string(i) + "].points.stride is too small");
            }
            polylines[i].points.resize(points.count);
            for (std::size_t p = 0; p < points.count; ++p) polylines[i].points[p] = points.at(p);
            polylines[i].closed = in.closed;
            const float* c = in.color;
            if (c[0] != 0.0f || c[1] != 0.0f || c[2] != 0.0f || c[3] != 0.0f) {
                polylines[i].color = {c[0], c[1], c[2], c[3]};
            }
        }
        return report(fn, renderer->impl->set_lines(polylines));
    });
}

DFM_API dfm_result dfm_vk_renderer_render_offscreen(dfm_vk_renderer* renderer,
                                                    const dfm_vk_frame* frame, uint8_t* rgba,
                                                    size_t rgba_size) {
    const char* fn = "dfm_vk_renderer_render_offscreen";
    return guarded(fn, [&]() -> dfm_result {
        if (!live(renderer)) return bad_handle(fn);
        render::ViewSettings view;
        if (dfm_result r = to_view(fn, frame, 0, 0, view); r != DFM_OK) return r;
        if (rgba != nullptr &&
            rgba_size != std::size_t{view.camera.width} * view.camera.height * 4) {
            return report(
                fn, DFM_ERROR_INVALID_ARGUMENT,
                "rgba_size must be camera.width * camera.height * 4 = " +
                    std::to_string(std::size_t{view.camera.width} * view.camera.height * 4));
        }
        return report(fn, renderer->impl->render_offscreen(
                              view, {rgba, rgba == nullptr ? std::size_t{0} : rgba_size}));
    });
}

DFM_API dfm_result dfm_vk_renderer_present(dfm_vk_renderer* renderer, const dfm_vk_frame* frame,
                                           bool* presented) {
    const char* fn = "dfm_vk_renderer_present";
    return guarded(
        fn, [&]() -> dfm_result { return present_frame(fn, renderer, frame, {}, presented); });
}

DFM_API dfm_result dfm_vk_renderer_present_and_read(dfm_vk_renderer* renderer,
                                                    const dfm_vk_frame* frame, uint8_t* rgba,
                                                    size_t rgba_size, bool* presented) {
    const char* fn = "dfm_vk_renderer_present_and_read";
    return guarded(fn, [&]() -> dfm_result {
        if (presented != nullptr) *presented = false;
        if (rgba == nullptr || rgba_size == 0) {
            return report(fn, DFM_ERROR_INVALID_ARGUMENT, "rgba is NULL or rgba_size is 0");
        }
        return present_frame(fn, renderer, frame, {rgba, rgba_size}, presented);
    });
}

DFM_API dfm_result dfm_vk_renderer_set_overlay(dfm_vk_renderer* renderer,
                                               const dfm_vk_overlay_desc* desc) {
    const char* fn = "dfm_vk_renderer_set_overlay";
    return guarded(fn, [&]() -> dfm_result {
        if (!live(renderer)) return bad_handle(fn);
        dfm_vk_overlay_desc overlay;
        if (dfm_result r = dfm::sdk::read_descriptor(fn, "desc", desc, overlay); r != DFM_OK) {
            return r;
        }
        if (!renderer->impl->has_window()) {
            return report(fn, DFM_ERROR_UNSUPPORTED,
                          "an overlay needs a renderer made for a window");
        }
        if (overlay.record == nullptr) {
            renderer->impl->set_overlay({});
            return DFM_OK;
        }
        dfm_result* result = &renderer->overlay_result;
        renderer->impl->set_overlay([overlay, result](const render::OverlayTarget& t) {
            dfm_vk_overlay_target target = {};
            target.struct_size = sizeof target;
            target.command_buffer = t.cmd;
            target.image = t.image;
            target.image_view = t.view;
            target.format = t.format;
            target.width = t.extent.width;
            target.height = t.extent.height;
            target.image_index = t.image_index;
            target.image_count = t.image_count;
            target.swapchain_generation = t.swapchain_generation;
            *result = overlay.record(overlay.user, &target);
            return dfm::Status::ok();
        });
        return DFM_OK;
    });
}

DFM_API dfm_result dfm_vk_renderer_get_device(const dfm_vk_renderer* renderer,
                                              dfm_vk_device_info* out) {
    const char* fn = "dfm_vk_renderer_get_device";
    return guarded(fn, [&]() -> dfm_result {
        dfm_vk_device_info info;
        if (dfm_result r = dfm::sdk::read_descriptor(fn, "out", out, info); r != DFM_OK) {
            return r;
        }
        // The host's struct_size says how many bytes are its own to write.
        const std::uint32_t struct_size = info.struct_size;
        const std::size_t size = dfm::sdk::host_struct_size<dfm_vk_device_info>(struct_size);
        if (!live(renderer)) return bad_handle(fn);
        const render::Gpu& gpu = renderer->impl->gpu();
        info = dfm_vk_device_info{};
        info.struct_size = struct_size;
        info.instance = gpu.instance;
        info.physical_device = gpu.physical;
        info.device = gpu.device;
        info.queue_family = gpu.queue_family;
        info.queue = gpu.queue;
        info.frames_in_flight = static_cast<uint32_t>(renderer->impl->frames_in_flight());
        info.samples = static_cast<uint32_t>(renderer->impl->samples());
        std::memcpy(out, &info, std::min(size, sizeof info));
        return DFM_OK;
    });
}

DFM_API dfm_result dfm_vk_renderer_record_upload(dfm_vk_renderer* renderer, VkCommandBuffer cmd) {
    const char* fn = "dfm_vk_renderer_record_upload";
    return guarded(fn, [&]() -> dfm_result {
        if (!live(renderer)) return bad_handle(fn);
        return report(fn, renderer->impl->record_upload(cmd));
    });
}

DFM_API dfm_result dfm_vk_renderer_record_draw(dfm_vk_renderer* renderer, VkCommandBuffer cmd,
                                               const dfm_vk_frame* frame, uint32_t width,
                                               uint32_t height) {
    const char* fn = "dfm_vk_renderer_record_draw";
    return guarded(fn, [&]() -> dfm_result {
        if (!live(renderer)) return bad_handle(fn);
        if (width == 0 || height == 0) {
            return report(fn, DFM_ERROR_INVALID_ARGUMENT, "width and height must be positive");
        }
        render::ViewSettings view;
        if (dfm_result r = to_view(fn, frame, width, height, view); r != DFM_OK) return r;
        return report(fn, renderer->impl->record_draw(cmd, view, {width, height}));
    });
}

DFM_API dfm_result dfm_vk_renderer_validation_message_count(const dfm_vk_renderer* renderer,
                                                            uint64_t* out) {
    const char* fn = "dfm_vk_renderer_validation_message_count";
    return guarded(fn, [&]() -> dfm_result {
        if (out == nullptr) return report(fn, DFM_ERROR_INVALID_ARGUMENT, "out is NULL");
        *out = 0;
        if (!live(renderer)) return bad_handle(fn);
        *out = renderer->impl->validation_messages();
        return DFM_OK;
    });
}

DFM_API dfm_result dfm_vk_renderer_sample_count(const dfm_vk_renderer* renderer, uint32_t* out) {
    const char* fn = "dfm_vk_renderer_sample_count";
    return guarded(fn, [&]() -> dfm_result {
        if (out == nullptr) return report(fn, DFM_ERROR_INVALID_ARGUMENT, "out is NULL");
        *out = 0;
        if (!live(renderer)) return bad_handle(fn);
        *out = static_cast<uint32_t>(renderer->impl->samples());
        return DFM_OK;
    });
}

DFM_API dfm_result dfm_vk_framing_camera(const dfm_vec3_input* positions, uint32_t width,
                                         uint32_t height, dfm_camera* out) {
    const char* fn = "dfm_vk_framing_camera";
    return guarded(fn, [&]() -> dfm_result {
        if (out == nullptr) return report(fn, DFM_ERROR_INVALID_ARGUMENT, "out is NULL");
        std::memset(out, 0, sizeof *out);
        if (positions == nullptr || (positions->count > 0 && positions->data == nullptr)) {
            return report(fn, DFM_ERROR_INVALID_ARGUMENT, "positions are NULL");
        }
        if (dfm_result r = check_scalar(fn, *positions); r != DFM_OK) return r;
        if (width == 0 || height == 0) {
            return report(fn, DFM_ERROR_INVALID_ARGUMENT, "width and height must be positive");
        }
        const render::StridedPositions points = to_strided(*positions);
        std::vector<glm::dvec3> read(points.count);
        for (std::size_t i = 0; i < points.count; ++i) read[i] = points.at(i);
        *out = dfm::sdk::to_c_camera(render::framing_camera(read, width, height));
        return DFM_OK;
    });
}

DFM_API dfm_result dfm_vk_write_png(const char* path, const uint8_t* rgba, size_t rgba_size,
                                    uint32_t width, uint32_t height) {
    const char* fn = "dfm_vk_write_png";
    return guarded(fn, [&]() -> dfm_result {
        if (path == nullptr || rgba == nullptr) {
            return report(fn, DFM_ERROR_INVALID_ARGUMENT, "path or rgba is NULL");
        }
        return report(fn, render::write_png(path, {rgba, rgba_size}, width, height));
    });
}

}  // extern "C"
