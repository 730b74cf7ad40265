#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <vector>

#include <vulkan/vulkan.h>

#include "render/command_frames.hpp"
#include "render/device.hpp"
#include "render/frame_uploader.hpp"
#include "render/gpu_memory.hpp"
#include "render/instance.hpp"
#include "render/offscreen_target.hpp"
#include "render/pipelines.hpp"
#include "render/scene_data.hpp"
#include "render/scene_draw.hpp"
#include "render/swapchain.hpp"
#include "render/validation.hpp"

namespace dfm::render {

// A window the renderer presents to, through whatever window system the
// host uses: the renderer links none (the GLFW backend is its own target,
// sdk/src/vulkan_glfw).
struct WindowSurface {
    // Instance extensions the surface needs (e.g. VK_KHR_surface and the
    // platform's); the strings must live until creation returns.
    std::vector<const char*> instance_extensions;
    // Creates the window's surface on the renderer's instance.
    std::function<VkResult(VkInstance, VkSurfaceKHR*)> create_surface;
    // The framebuffer's size in pixels now; 0 × 0 while minimised.
    std::function<VkExtent2D()> framebuffer_extent;
};

// Where a host records its own drawing into a window frame, after the mesh:
// the swapchain image, a colour attachment in COLOR_ATTACHMENT_OPTIMAL that
// the host leaves in that layout.
struct OverlayTarget {
    VkCommandBuffer cmd = VK_NULL_HANDLE;
    VkImage image = VK_NULL_HANDLE;
    VkImageView view = VK_NULL_HANDLE;
    VkFormat format = VK_FORMAT_UNDEFINED;
    VkExtent2D extent{};
    std::uint32_t image_index = 0;
    std::uint32_t image_count = 0;
    // Grows whenever the swapchain is rebuilt: what the host made for the
    // images of an older one (framebuffers) is stale.
    std::uint64_t swapchain_generation = 0;
};
using Overlay = std::function<Status(const OverlayTarget&)>;

// Settings of a renderer that creates its own instance and device.
struct OwnDeviceOptions {
    std::size_t frames_in_flight = 2;
    // Upper bound on MSAA; the device's best up to this is used.
    VkSampleCountFlagBits max_samples = VK_SAMPLE_COUNT_4_BIT;
    bool validation = false;
    bool vsync = true;  // window path
};

// Handles a host created, and what the host renders into.
struct HostDevice {
    Gpu gpu;  // instance, physical, device, queue_family, queue; wireframe:
              // whether the host enabled fillModeNonSolid
    AttachmentFormats formats;
    std::size_t frames_in_flight = 2;
};

// Draws a mesh with its ROI / handle / fixed highlight, a wireframe and host
// lines. Three ways in: headless (own device, offscreen picture read back),
// a window (own device, swapchain), or a host's device (the draw is
// recorded into the host's command buffer inside the host's dynamic
// rendering). Not thread-safe: one thread at a time.
class Renderer {
public:
    Renderer(const Renderer&) = delete;
    Renderer& operator=(const Renderer&) = delete;
    ~Renderer();

    static Status create_headless(const OwnDeviceOptions& options, std::unique_ptr<Renderer>& out);
    static Status create_window(const OwnDeviceOptions& options, WindowSurface window,
                                std::unique_ptr<Renderer>& out);
    static Status create_host(const HostDevice& host, std::unique_ptr<Renderer>& out);

    Status set_mesh(const StridedPositions& positions,
                    std::span<const std::uint32_t> triangle_indices);
    Status set_positions(const StridedPositions& positions);
    Status set_marks(std::span<const std::uint8_t> marks);
    Status set_lines(std::span<const Polyline> lines);
    const SceneData& scene() const { return scene_; }

    // Draws a camera.width × camera.height picture offscreen. With `rgba`
    // (width × height × 4 bytes) it waits and reads the picture back; empty,
    // it returns once the frame is submitted (frames stay in flight).
    Status render_offscreen(const ViewSettings& view, std::span<std::uint8_t> rgba);

    // Window path: draws and presents one frame at the window's framebuffer
    // size (the camera's width and height are ignored), the overlay (if set)
    // drawn after the mesh. `presented` is false when the window is minimised
    // or the swapchain had to be rebuilt. With `rgba` (width x height x 4
    // bytes of the window's picture) it waits for the frame and copies what
    // it presented, overlay included, into it (RGBA, rows top to bottom).
    Status present(const ViewSettings& view, bool& presented, std::span<std::uint8_t> rgba = {});
    // Window path: called inside every present, after the mesh's draw. An
    // empty function removes it.
    void set_overlay(Overlay overlay) { overlay_ = std::move(overlay); }
    bool has_window() const { return static_cast<bool>(window_extent_); }
    const Gpu& gpu() const { return gpu_; }
    std::size_t frames_in_flight() const { return uploader_.slot_count(); }

    // Host path: the vertex upload (outside rendering), then the draw (inside
    // the host's dynamic rendering of `extent`). Each record_upload moves to
    // the next of frames_in_flight buffer sets; the host guarantees the GPU
    // finished the command buffer recorded frames_in_flight uploads ago.
    Status record_upload(VkCommandBuffer cmd);
    Status record_draw(VkCommandBuffer cmd, const ViewSettings& view, VkExtent2D extent);

    // Validation warnings and errors seen so far (own-device modes).
    std::uint64_t validation_messages() const { return counter_->count(); }
    VkSampleCountFlagBits samples() const { return formats_.samples; }
    bool owns_device() const { return owned_device_.gpu().device != VK_NULL_HANDLE; }

private:
    explicit Renderer(std::size_t frames_in_flight) : uploader_(frames_in_flight) {}

    // `window` null: headless.
    Status create_own(const OwnDeviceOptions& options, const WindowSurface* window);
    Status wait_idle() const;
    Status rebuild_swapchain(bool& usable);
    Status check_usable() const;
    // Remembers that the device failed mid-frame: later calls refuse to run.
    Status broken(Status status);
    DrawBuffers draw_buffers(std::size_t slot) const;

    // Declaration order is destruction order reversed: everything made from
    // the device goes before it, the surface before the instance.
    std::unique_ptr<ValidationCounter> counter_ = std::make_unique<ValidationCounter>();
    Instance instance_;
    VkSurfaceKHR surface_ = VK_NULL_HANDLE;
    std::function<VkExtent2D()> window_extent_;  // empty unless made for a window
    Device owned_device_;
    Gpu gpu_;
    AttachmentFormats formats_;
    VkSurfaceFormatKHR surface_format_{};
    bool vsync_ = true;
    bool failed_ = false;
    std::size_t host_slot_ = 0;
    // Host path: record_upload calls so far, and index buffers replaced by
    // set_mesh that a draw recorded after upload `last_upload` may still read.
    struct RetiredBuffer {
        GpuBuffer buffer;
        std::size_t last_upload = 0;
    };
    std::size_t host_uploads_ = 0;
    CommandFrames frames_;
    Pipelines pipelines_;
    FrameUploader uploader_;
    GpuBuffer indices_;
    std::vector<RetiredBuffer> retired_indices_;
    std::optional<OffscreenTarget> offscreen_;
    std::unique_ptr<Swapchain> swapchain_;
    std::uint64_t swapchain_generation_ = 0;
    Overlay overlay_;
    GpuBuffer window_readback_;
    SceneData scene_;
};

}  // namespace dfm::render
