#include "render/renderer.hpp"

#include <algorithm>
#include <cstring>
#include <string>
#include <utility>

namespace dfm::render {

namespace {

constexpr VkFormat offscreen_color = VK_FORMAT_R8G8B8A8_UNORM;
constexpr VkFormat depth_format = VK_FORMAT_D32_SFLOAT;

}  // namespace

Renderer::~Renderer() {
    // On a host's device nothing is waited for: the host's queue is the
    // host's, and it has finished the command buffers we recorded into
    // before it destroys us (dualform_vulkan.h says so).
    if (owns_device()) vkDeviceWaitIdle(gpu_.device);
    swapchain_.reset();
    if (surface_ != VK_NULL_HANDLE) vkDestroySurfaceKHR(instance_.handle(), surface_, nullptr);
}

Status Renderer::create_own(const OwnDeviceOptions& options, const WindowSurface* window) {
    const std::vector<const char*> no_extensions;
    if (Status s = Instance::create(window != nullptr ? window->instance_extensions : no_extensions,
                                    options.validation, *counter_, instance_);
        !s) {
        return s;
    }
    if (window != nullptr) {
        if (VkResult r = window->create_surface(instance_.handle(), &surface_); r != VK_SUCCESS) {
            surface_ = VK_NULL_HANDLE;
            return vk_failure(r, "creating the window's surface");
        }
        window_extent_ = window->framebuffer_extent;
    }
    if (Status s = Device::create(instance_.handle(), surface_, owned_device_); !s) return s;
    gpu_ = owned_device_.gpu();
    vsync_ = options.vsync;
    formats_.color = offscreen_color;
    formats_.depth = depth_format;
    formats_.samples = std::min(best_sample_count(gpu_.physical), options.max_samples);
    if (window != nullptr) {
        if (Status s = Swapchain::choose_format(gpu_, surface_, surface_format_); !s) {
            return s;
        }
        formats_.color = surface_format_.format;
    }
    if (Status s = frames_.create(gpu_, uploader_.slot_count()); !s) return s;
    return pipelines_.create(gpu_.device, formats_, gpu_.wireframe);
}

Status Renderer::create_headless(const OwnDeviceOptions& options, std::unique_ptr<Renderer>& out) {
    if (options.frames_in_flight == 0 || options.frames_in_flight > 8) {
        return Status(Errc::invalid_argument, "frames_in_flight must lie in 1..8");
    }
    std::unique_ptr<Renderer> r(new Renderer(options.frames_in_flight));
    if (Status s = r->create_own(options, nullptr); !s) return s;
    out = std::move(r);
    return Status::ok();
}

Status Renderer::create_window(const OwnDeviceOptions& options, WindowSurface window,
                               std::unique_ptr<Renderer>& out) {
    if (!window.create_surface || !window.framebuffer_extent) {
        return Status(Errc::invalid_argument,
                      "a window needs its create_surface and framebuffer_size functions");
    }
    if (options.frames_in_flight == 0 || options.frames_in_flight > 8) {
        return Status(Errc::invalid_argument, "frames_in_flight must lie in 1..8");
    }
    std::unique_ptr<Renderer> r(new Renderer(options.frames_in_flight));
    if (Status s = r->create_own(options, &window); !s) return s;
    out = std::move(r);
    return Status::ok();
}

Status Renderer::create_host(const HostDevice& host, std::unique_ptr<Renderer>& out) {
    if (host.frames_in_flight == 0 || host.frames_in_flight > 8) {
        return Status(Errc::invalid_argument, "frames_in_flight must lie in 1..8");
    }
    if (host.formats.color == VK_FORMAT_UNDEFINED) {
        return Status(Errc::invalid_argument, "the host's colour format is needed");
    }
    std::unique_ptr<Renderer> r(new Renderer(host.frames_in_flight));
    r->gpu_ = host.gpu;
    if (Status s = describe_host_gpu(r->gpu_); !s) {
        r->gpu_.device = VK_NULL_HANDLE;
        return s;
    }
    r->formats_ = host.formats;
    if (Status s = r->pipelines_.create(r->gpu_.device, r->formats_, r->gpu_.wireframe); !s) {
        return s;
    }
    out = std::move(r);
    return Status::ok();
}

Status Renderer::check_usable() const {
    if (failed_) {
        return Status(Errc::device, "the renderer is unusable after an earlier device failure");
    }
    return Status::ok();
}

Status Renderer::broken(Status status) {
    if (!status) failed_ = true;
    return status;
}

Status Renderer::wait_idle() const {
    // Own devices only: a host's queue is never waited on.
    const VkResult r = vkDeviceWaitIdle(gpu_.device);
    return r == VK_SUCCESS ? Status::ok() : vk_failure(r, "waiting for the device");
}

Status Renderer::set_mesh(const StridedPositions& positions,
                          std::span<const std::uint32_t> triangle_indices) {
    if (Status s = check_usable(); !s) return s;
    SceneData next = scene_;
    if (Status s = next.set_mesh(positions, triangle_indices); !s) return s;
    // The index buffer is replaced while frames in flight may still read the
    // old one. Our own device is waited for; a host's is not: the old buffer
    // lives on until the host's frame fence covers the last draw that used it.
    if (owns_device()) {
        if (Status s = wait_idle(); !s) return broken(s);
    }
    GpuBuffer indices;
    if (Status s = GpuBuffer::create(gpu_, next.indices().size_bytes(),
                                     VK_BUFFER_USAGE_INDEX_BUFFER_BIT, true, indices);
        !s) {
        return s;
    }
    std::memcpy(indices.mapped(), next.indices().data(), next.indices().size_bytes());
    if (!owns_device() && indices_.handle() != VK_NULL_HANDLE) {
        retired_indices_.push_back({std::move(indices_), host_uploads_});
    }
    indices_ = std::move(indices);
    scene_ = std::move(next);
    return Status::ok();
}

Status Renderer::set_positions(const StridedPositions& positions) {
    return scene_.set_positions(positions);
}

Status Renderer::set_marks(std::span<const std::uint8_t> marks) {
    if (!scene_.has_mesh()) return Status(Errc::invalid_argument, "marks: no mesh set");
    return scene_.set_marks(marks);
}

Status Renderer::set_lines(std::span<const Polyline> lines) {
    return scene_.set_lines(lines);
}

DrawBuffers Renderer::draw_buffers(std::size_t slot) const {
    DrawBuffers b;
    b.mesh_vertices = uploader_.mesh_vertices(slot);
    b.line_vertices = uploader_.line_vertices(slot);
    b.indices = indices_.handle();
    b.index_count = scene_.has_mesh() ? scene_.index_count() : 0;
    b.line_vertex_count = static_cast<std::uint32_t>(scene_.line_vertices().size());
    return b;
}

Status Renderer::render_offscreen(const ViewSettings& view, std::span<std::uint8_t> rgba) {
    if (Status s = check_usable(); !s) return s;
    if (!owns_device()) {
        return Status(Errc::unsupported,
                      "offscreen rendering needs a renderer with its own device; a host "
                      "device records into its own command buffers");
    }
    const VkExtent2D extent{view.camera.width, view.camera.height};
    if (extent.width == 0 || extent.height == 0 || extent.width > 16384 || extent.height > 16384) {
        return Status(Errc::invalid_argument, "camera width and height must lie in 1..16384");
    }
    if (!rgba.empty() && rgba.size() != std::size_t{extent.width} * extent.height * 4) {
        return Status(Errc::invalid_argument,
                      "the pixel buffer must hold width x height x 4 bytes");
    }
    if (!offscreen_ || offscreen_->extent().width != extent.width ||
        offscreen_->extent().height != extent.height) {
        if (Status s = wait_idle(); !s) return broken(s);
        OffscreenTarget target;
        if (Status s = OffscreenTarget::create(gpu_, formats_, extent, target); !s) return s;
        offscreen_ = std::move(target);
    }
    if (Status s = frames_.wait_current(); !s) return broken(s);
    const std::size_t slot = frames_.current();
    if (Status s = uploader_.stage(gpu_, slot, scene_); !s) return s;
    if (Status s = frames_.begin_current(); !s) return broken(s);
    const VkCommandBuffer cmd = frames_.command_buffer();
    uploader_.record_copy(cmd, slot);
    offscreen_->record_begin(cmd, &view.background[0]);
    record_scene_draw(cmd, pipelines_, draw_buffers(slot), view, scene_.bounds(), extent);
    offscreen_->record_end_and_copy(cmd);
    if (Status s = frames_.submit_current(VK_NULL_HANDLE, VK_NULL_HANDLE); !s) {
        return broken(s);
    }
    if (!rgba.empty()) {
        if (Status s = frames_.wait_current(); !s) return broken(s);
        const std::span<const std::uint8_t> picture = offscreen_->pixels();
        std::memcpy(rgba.data(), picture.data(), picture.size());
        // A window renderer draws in its swapchain's format, which may be
        // BGRA; the caller always gets RGBA.
        if (formats_.color == VK_FORMAT_B8G8R8A8_UNORM ||
            formats_.color == VK_FORMAT_B8G8R8A8_SRGB) {
            for (std::size_t i = 0; i + 3 < rgba.size(); i += 4) std::swap(rgba[i], rgba[i + 2]);
        }
    }
    frames_.advance();
    return Status::ok();
}

Status Renderer::rebuild_swapchain(bool& usable) {
    usable = false;
    const VkExtent2D extent = window_extent_();
    if (extent.width == 0 || extent.height == 0) return Status::ok();
    if (Status s = wait_idle(); !s) return s;
    swapchain_.reset();
    auto next = std::make_unique<Swapchain>();
    if (Status s =
            Swapchain::create(gpu_, surface_, formats_, surface_format_, extent, vsync_, *next);
        !s) {
        return s;
    }
    swapchain_ = std::move(next);
    ++swapchain_generation_;
    usable = true;
    return Status::ok();
}

Status Renderer::present(const ViewSettings& view, bool& presented, std::span<std::uint8_t> rgba) {
    presented = false;
    if (Status s = check_usable(); !s) return s;
    if (!window_extent_) {
        return Status(Errc::unsupported, "present needs a renderer made for a window");
    }
    const VkExtent2D extent = window_extent_();
    if (extent.width == 0 || extent.height == 0) return Status::ok();  // minimised
    if (!swapchain_ || swapchain_->extent().width != extent.width ||
        swapchain_->extent().height != extent.height) {
        bool usable = false;
        if (Status s = rebuild_swapchain(usable); !s) return broken(s);
        if (!usable) return Status::ok();
    }
    const VkExtent2D shown_extent = swapchain_->extent();
    const std::size_t picture_bytes = std::size_t{shown_extent.width} * shown_extent.height * 4;
    if (!rgba.empty()) {
        if (!swapchain_->readable()) {
            return Status(Errc::unsupported,
                          "this window's surface does not let its pictures be read");
        }
        if (rgba.size() != picture_bytes) {
            return Status(Errc::invalid_argument, "the window's picture is " +
                                                      std::to_string(shown_extent.width) + " x " +
                                                      std::to_string(shown_extent.height) +
                                                      ": the pixel buffer must hold " +
                                                      std::to_string(picture_bytes) + " bytes");
        }
        if (window_readback_.handle() == VK_NULL_HANDLE ||
            window_readback_.size() != picture_bytes) {
            GpuBuffer readback;
            if (Status s = GpuBuffer::create(gpu_, picture_bytes, VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                                             true, readback);
                !s) {
                return s;
            }
            window_readback_ = std::move(readback);
        }
    }
    if (Status s = frames_.wait_current(); !s) return broken(s);
    std::uint32_t image = 0;
    const VkResult acquired = vkAcquireNextImageKHR(gpu_.device, swapchain_->handle(), UINT64_MAX,
                                                    frames_.acquired(), VK_NULL_HANDLE, &image);
    if (acquired == VK_ERROR_OUT_OF_DATE_KHR) {
        bool usable = false;
        return broken(rebuild_swapchain(usable));
    }
    if (acquired != VK_SUCCESS && acquired != VK_SUBOPTIMAL_KHR) {
        return broken(vk_failure(acquired, "vkAcquireNextImageKHR"));
    }
    const std::size_t slot = frames_.current();
    if (Status s = uploader_.stage(gpu_, slot, scene_); !s) return s;
    if (Status s = frames_.begin_current(); !s) return broken(s);
    const VkCommandBuffer cmd = frames_.command_buffer();
    uploader_.record_copy(cmd, slot);
    swapchain_->record_begin(cmd, image, &view.background[0]);
    record_scene_draw(cmd, pipelines_, draw_buffers(slot), view, scene_.bounds(),
                      swapchain_->extent());
    swapchain_->record_end_rendering(cmd, image);
    // A failing overlay still lets the frame finish (the acquired image must
    // be presented); its status is the call's.
    Status overlaid = Status::ok();
    if (overlay_) {
        OverlayTarget target;
        target.cmd = cmd;
        target.image = swapchain_->image(image);
        target.view = swapchain_->view(image);
        target.format = swapchain_->format();
        target.extent = swapchain_->extent();
        target.image_index = image;
        target.image_count = swapchain_->image_count();
        target.swapchain_generation = swapchain_generation_;
        overlaid = overlay_(target);
    }
    const bool copy = !rgba.empty();
    if (copy) swapchain_->record_copy(cmd, image, window_readback_.handle());
    swapchain_->record_present_ready(cmd, image, copy);
    const VkSemaphore rendered = swapchain_->rendered(image);
    if (Status s = frames_.submit_current(frames_.acquired(), rendered); !s) {
        return broken(s);
    }
    if (copy) {
        if (Status s = frames_.wait_current(); !s) return broken(s);
        std::memcpy(rgba.data(), window_readback_.mapped(), picture_bytes);
        if (swapchain_->format() == VK_FORMAT_B8G8R8A8_UNORM ||
            swapchain_->format() == VK_FORMAT_B8G8R8A8_SRGB) {
            for (std::size_t i = 0; i + 3 < rgba.size(); i += 4) std::swap(rgba[i], rgba[i + 2]);
        }
    }
    frames_.advance();

    const VkSwapchainKHR handle = swapchain_->handle();
    VkPresentInfoKHR info{};
    info.sType = VK_STRUCTURE_TYPE_PRESENT_INFO_KHR;
    info.waitSemaphoreCount = 1;
    info.pWaitSemaphores = &rendered;
    info.swapchainCount = 1;
    info.pSwapchains = &handle;
    info.pImageIndices = &image;
    const VkResult shown = vkQueuePresentKHR(gpu_.queue, &info);
    if (shown == VK_ERROR_OUT_OF_DATE_KHR || shown == VK_SUBOPTIMAL_KHR) {
        bool usable = false;
        return broken(rebuild_swapchain(usable));
    }
    if (shown != VK_SUCCESS) return broken(vk_failure(shown, "vkQueuePresentKHR"));
    presented = true;
    return overlaid;
}

Status Renderer::record_upload(VkCommandBuffer cmd) {
    if (owns_device()) {
        return Status(Errc::unsupported, "record_upload is for renderers on a host's device");
    }
    if (cmd == VK_NULL_HANDLE) return Status(Errc::invalid_argument, "command buffer is NULL");
    host_slot_ = (host_slot_ + 1) % uploader_.slot_count();
    // The host guarantees the GPU finished what it recorded slot_count
    // uploads ago, so a buffer retired before then is no longer read.
    ++host_uploads_;
    std::erase_if(retired_indices_, [&](const RetiredBuffer& r) {
        return r.last_upload + uploader_.slot_count() <= host_uploads_;
    });
    if (Status s = uploader_.stage(gpu_, host_slot_, scene_); !s) return s;
    uploader_.record_copy(cmd, host_slot_);
    return Status::ok();
}

Status Renderer::record_draw(VkCommandBuffer cmd, const ViewSettings& view, VkExtent2D extent) {
    if (owns_device()) {
        return Status(Errc::unsupported, "record_draw is for renderers on a host's device");
    }
    if (cmd == VK_NULL_HANDLE) return Status(Errc::invalid_argument, "command buffer is NULL");
    if (extent.width == 0 || extent.height == 0) {
        return Status(Errc::invalid_argument, "the extent must be non-empty");
    }
    if (uploader_.mesh_vertices(host_slot_) == VK_NULL_HANDLE) {
        return Status(Errc::invalid_argument, "record_upload must come before record_draw");
    }
    record_scene_draw(cmd, pipelines_, draw_buffers(host_slot_), view, scene_.bounds(), extent);
    return Status::ok();
}

}  // namespace dfm::render
