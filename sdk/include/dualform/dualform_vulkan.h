/*
 * Dualform's Vulkan renderer: the public C API (libdualform_vulkan).
 *
 * Separate from dualform.h so that the deformation API never needs Vulkan.
 * It draws a triangle mesh lit (smooth normals recomputed whenever positions
 * change, or flat), each vertex coloured by its mark (ROI red, handles green,
 * the fixed part blue), with an optional wireframe and host polylines (the
 * region line, a cutting loop) over it, MSAA where the device has it.
 *
 * Three ways in:
 * - headless: the renderer creates its own instance and device and renders
 *   offscreen pictures that it reads back (dfm_vk_renderer_render_offscreen);
 * - a window: its own instance and device, and a swapchain on the window's
 *   surface, through the host's window system (dfm_vk_window); this library
 *   links none, and dualform_vulkan_glfw.h is a small backend for GLFW
 *   (dfm_vk_renderer_present); the host may record its own drawing (a user
 *   interface) into each window frame after the mesh
 *   (dfm_vk_renderer_set_overlay) and read the presented picture back
 *   (dfm_vk_renderer_present_and_read);
 * - the host's device: the host hands its instance, physical device, device,
 *   queue family and queue; the renderer records its upload and draw into the
 *   host's command buffer, inside the host's Vulkan 1.3 dynamic rendering.
 *
 * Conventions are dualform.h's: every call returns a dfm_result (Vulkan
 * failures are DFM_ERROR_DEVICE), the message is dfm_last_error_message(),
 * descriptors are valid when zero-initialised, dfm_vk_renderer_destroy(NULL)
 * is a no-op, nothing throws or aborts on bad input. A renderer is not
 * thread-safe: call it from one thread at a time (different renderers may be
 * used from different threads).
 *
 * With dfm_vk_renderer_desc.validation, a renderer that owns its instance
 * turns on VK_LAYER_KHRONOS_validation (creation fails when it is not
 * installed) and counts every warning and error the layer reports
 * (dfm_vk_renderer_validation_message_count). The library reads no
 * environment variable; the tools and samples turn it on for
 * DUALFORM_VALIDATION=1.
 */
#ifndef DUALFORM_DUALFORM_VULKAN_H
#define DUALFORM_DUALFORM_VULKAN_H

#include <vulkan/vulkan.h>

#include "dualform/dualform.h"

#ifdef __cplusplus
extern "C" {
#endif

/* An opaque renderer. */
typedef struct dfm_vk_renderer dfm_vk_renderer;

/* Per-vertex marks (dfm_vk_renderer_set_marks). */
typedef enum dfm_vk_mark {
    DFM_VK_MARK_SURFACE = 0, /* not part of the edit: the plain surface colour */
    DFM_VK_MARK_ROI = 1,     /* region of interest: red */
    DFM_VK_MARK_HANDLE = 2,  /* handle: green */
    DFM_VK_MARK_FIXED = 3    /* fixed / anchored part: blue */
} dfm_vk_mark;

/* Frame flags (dfm_vk_frame.flags). */
#define DFM_VK_FLAG_WIREFRAME 0x1u /* draw the triangle edges over the surface */
#define DFM_VK_FLAG_FLAT 0x2u      /* flat shading (one normal per triangle) */

/* Positions are dualform.h's dfm_vec3_input: `count` x y z triples of
 * `type` (float by default, or double), `stride` bytes apart (0: packed), so
 * a host passes its own vertex array, or what the deformation SDK wrote. */

/* A polyline in world space (the region line, the cutting plane's loop). */
typedef struct dfm_vk_polyline {
    dfm_vec3_input points; /* the polyline's corners, in order */
    bool closed;           /* joins the last point back to the first */
    float color[4];        /* RGBA 0..1; all zero: yellow */
} dfm_vk_polyline;

/* How one frame looks. */
typedef struct dfm_vk_frame {
    dfm_camera camera;   /* for the offscreen path its width x height is the picture size;
                            the window and host paths use their own extent */
    uint32_t flags;      /* DFM_VK_FLAG_* */
    float background[4]; /* RGBA 0..1; all zero: dark slate */
} dfm_vk_frame;

/* Creating a renderer with its own instance and device. */
typedef struct dfm_vk_renderer_desc {
    uint32_t frames_in_flight; /* 0: 2; at most 8 */
    uint32_t max_samples;      /* MSAA upper bound: 0 = 4, 1 = off, 2 or 4 */
    bool no_vsync;             /* window path: present without waiting for vertical sync */
    bool validation;           /* turn on VK_LAYER_KHRONOS_validation and count its messages */
} dfm_vk_renderer_desc;

/* The host's Vulkan objects (all borrowed: the renderer never destroys them).
 * The device must be Vulkan 1.3 with dynamicRendering enabled. */
typedef struct dfm_vk_host_desc {
    VkInstance instance;              /* the host's instance */
    VkPhysicalDevice physical_device; /* the device's physical device */
    VkDevice device;                  /* the host's device, Vulkan 1.3, dynamicRendering on */
    uint32_t queue_family;            /* the family of `queue` */
    VkQueue queue;                 /* the queue the host submits our commands on; the renderer never
                                      submits to it nor waits on it */
    VkFormat color_format;         /* the host's colour attachment; required */
    VkFormat depth_format;         /* VK_FORMAT_UNDEFINED (0): no depth attachment */
    VkSampleCountFlagBits samples; /* of the host's attachments; 0: 1 */
    uint32_t frames_in_flight;     /* 0: 2; at most 8 */
    bool fill_mode_non_solid;      /* the host enabled fillModeNonSolid: wireframe works */
} dfm_vk_host_desc;

/* Creates a renderer with its own instance and device, drawing offscreen.
 * `desc` may be NULL (defaults). On success *out owns the renderer (free it
 * with dfm_vk_renderer_destroy); on failure *out is NULL and the result says
 * why (DFM_ERROR_UNSUPPORTED: no Vulkan 1.3 device, or validation asked for
 * and not installed; DFM_ERROR_DEVICE: Vulkan failed). Thread-safe. */
DFM_API dfm_result dfm_vk_renderer_create_headless(const dfm_vk_renderer_desc* desc,
                                                   dfm_vk_renderer** out);

/* A window the renderer presents to, described through the host's window
 * system (GLFW, SDL, a platform's own): copied at creation; `user` and what
 * it points to must outlive the renderer. dualform_vulkan_glfw.h fills one
 * for a GLFW window. */
typedef struct dfm_vk_window {
    const char* const* instance_extensions; /* what the surface needs (VK_KHR_surface, ...) */
    uint32_t instance_extension_count;      /* entries of instance_extensions */
    /* Creates the window's surface on the renderer's instance; required. */
    VkResult (*create_surface)(void* user, VkInstance instance, VkSurfaceKHR* out);
    /* The framebuffer's size in pixels now (0 x 0 while minimised); required. */
    void (*framebuffer_size)(void* user, uint32_t* width, uint32_t* height);
    void* user; /* passed to both functions */
} dfm_vk_window;

/* Creates a renderer with its own instance and device that presents to a
 * window (dfm_vk_renderer_present). DFM_ERROR_INVALID_ARGUMENT for a NULL
 * window or function; other errors and ownership as
 * dfm_vk_renderer_create_headless. Call from the thread that owns the
 * window. */
DFM_API dfm_result dfm_vk_renderer_create_for_window(const dfm_vk_renderer_desc* desc,
                                                     const dfm_vk_window* window,
                                                     dfm_vk_renderer** out);

/* Creates a renderer on the host's device (see dfm_vk_host_desc). *out as
 * above. DFM_ERROR_INVALID_ARGUMENT for missing handles or formats. The
 * validation count stays 0: the host owns its instance's messages. */
DFM_API dfm_result dfm_vk_renderer_create_host(const dfm_vk_host_desc* desc, dfm_vk_renderer** out);

/* Frees the renderer and everything it created (never the host's objects).
 * A renderer with its own device first waits until that device is idle. A
 * renderer on a host's device waits for nothing: the host must have finished
 * the command buffers it recorded into (its frame fences, or
 * vkDeviceWaitIdle) before it calls this. NULL is a no-op. No other call on
 * this renderer may run meanwhile, nor follow. */
DFM_API void dfm_vk_renderer_destroy(dfm_vk_renderer* renderer);

/* Sets the mesh: positions and `triangle_count` triangles of three uint32
 * indices. Both arrays are copied. Marks reset to DFM_VK_MARK_SURFACE; lines
 * stay. With its own device the renderer waits for the frames in flight; on
 * a host's device it waits for nothing and keeps the old buffers until the
 * host's frame fences cover them (see dfm_vk_renderer_record_upload). Errors:
 * DFM_ERROR_INVALID_ARGUMENT (no triangles, an index past the vertices, a
 * non-finite position, a stride smaller than a triple); nothing changes then.
 * Not thread-safe per renderer (as every call below taking one). */
DFM_API dfm_result dfm_vk_renderer_set_mesh(dfm_vk_renderer* renderer,
                                            const dfm_vec3_input* positions,
                                            const uint32_t* triangle_indices,
                                            size_t triangle_count);

/* New positions for the mesh's vertices (same count), e.g. after each
 * deformation; copied, smooth normals recomputed. They reach the GPU with the
 * next frame, through per-frame staging buffers: no stall. The caller keeps
 * its array. DFM_ERROR_INVALID_ARGUMENT for another count, a non-finite
 * position or no mesh; the previous positions stay. Not thread-safe. */
DFM_API dfm_result dfm_vk_renderer_update_positions(dfm_vk_renderer* renderer,
                                                    const dfm_vec3_input* positions);

/* One dfm_vk_mark per vertex (`count` = the mesh's vertex count), copied; NULL
 * with count 0 clears them. DFM_ERROR_INVALID_ARGUMENT for a wrong count or a
 * value above 3 (the marks stay as they were). Not thread-safe. */
DFM_API dfm_result dfm_vk_renderer_set_marks(dfm_vk_renderer* renderer, const uint8_t* marks,
                                             size_t count);

/* Replaces the polylines drawn over the mesh (copied; one pixel wide, drawn
 * just in front of the surface); NULL with count 0 removes them.
 * DFM_ERROR_INVALID_ARGUMENT for NULL points or a non-finite point (the lines
 * stay as they were). Not thread-safe. */
DFM_API dfm_result dfm_vk_renderer_set_lines(dfm_vk_renderer* renderer,
                                             const dfm_vk_polyline* lines, size_t count);

/* Headless and window renderers: draws one frame offscreen at
 * frame->camera.width x height (1 to 16384 each) and, when `rgba` is not NULL,
 * waits for it and copies it into `rgba` (rgba_size = width * height * 4
 * bytes, rows top to bottom, RGBA8). With `rgba` NULL the frame is only
 * submitted (frames stay in flight; for timing). The caller owns `rgba`.
 * DFM_ERROR_INVALID_ARGUMENT for a bad camera, flags or size;
 * DFM_ERROR_UNSUPPORTED on a host-device renderer; DFM_ERROR_DEVICE when
 * Vulkan fails (the renderer then refuses further frames). Not thread-safe. */
DFM_API dfm_result dfm_vk_renderer_render_offscreen(dfm_vk_renderer* renderer,
                                                    const dfm_vk_frame* frame, uint8_t* rgba,
                                                    size_t rgba_size);

/* Window renderers: draws and presents one frame at the window's framebuffer
 * size, rebuilding the swapchain after a resize. When the window is minimised
 * (or the swapchain was just rebuilt) nothing is shown and *presented (if not
 * NULL) is false; that is not an error. DFM_ERROR_UNSUPPORTED without a
 * window. Call from the window's thread; not thread-safe. */
DFM_API dfm_result dfm_vk_renderer_present(dfm_vk_renderer* renderer, const dfm_vk_frame* frame,
                                           bool* presented);

/* ------------------------------------------------------------ window overlay
 * A window renderer owns its frame, but the host may draw into it: an overlay
 * (a user interface, a heads-up display) recorded after the mesh into the
 * same command buffer and swapchain image, then presented with it. */

/* Where the overlay draws, handed to dfm_vk_overlay_fn for each frame. */
typedef struct dfm_vk_overlay_target {
    uint32_t struct_size;           /* sizeof this struct as the library has it; fields only
                                       ever appear at the end */
    VkCommandBuffer command_buffer; /* recording, outside any rendering; the renderer's: record
                                       into it, never submit, end or reset it */
    VkImage image;                  /* the swapchain image, the mesh drawn (resolved when
                                       multisampled), in VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL
                                       with the mesh's writes visible to colour-attachment reads
                                       and writes; leave it in that layout, written at
                                       VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT */
    VkImageView image_view;         /* a 2D colour view of `image` (a framebuffer's attachment) */
    VkFormat format;                /* the swapchain's format */
    uint32_t width;                 /* the image's width in pixels */
    uint32_t height;                /* and its height */
    uint32_t image_index;           /* which swapchain image: 0 .. image_count - 1 */
    uint32_t image_count;           /* the swapchain's images */
    uint64_t swapchain_generation;  /* grows each time the swapchain is rebuilt (a resize):
                                       views and framebuffers kept from an older one are stale */
} dfm_vk_overlay_target;

/* Records the host's drawing into target->command_buffer; called from inside
 * dfm_vk_renderer_present / dfm_vk_renderer_present_and_read on their thread.
 * It must not call the renderer. A result other than DFM_OK still lets the
 * frame be presented, and becomes that call's result. */
typedef dfm_result (*dfm_vk_overlay_fn)(void* user, const dfm_vk_overlay_target* target);

/* An overlay for dfm_vk_renderer_set_overlay; zero: none. */
typedef struct dfm_vk_overlay_desc {
    uint32_t struct_size;     /* sizeof(dfm_vk_overlay_desc); see dualform.h's conventions */
    dfm_vk_overlay_fn record; /* NULL: no overlay */
    void* user;               /* passed to `record`; must outlive the overlay */
} dfm_vk_overlay_desc;

/* Window renderers: sets (or with desc->record NULL, removes) the overlay
 * every later present records after the mesh. The overlay's Vulkan objects
 * are the host's, made on the renderer's device (dfm_vk_renderer_get_device);
 * the host destroys them after vkDeviceWaitIdle on that device and before
 * dfm_vk_renderer_destroy. DFM_ERROR_UNSUPPORTED on a renderer without a
 * window; DFM_ERROR_INVALID_ARGUMENT for a NULL desc. Not thread-safe. */
DFM_API dfm_result dfm_vk_renderer_set_overlay(dfm_vk_renderer* renderer,
                                               const dfm_vk_overlay_desc* desc);

/* The Vulkan objects of a renderer's device, for a host that makes its own
 * objects on it (an overlay's pipeline, descriptor pool). All stay the
 * renderer's: never destroy them. The host may submit to `queue` only from
 * the thread that uses the renderer, between its calls. */
typedef struct dfm_vk_device_info {
    uint32_t struct_size;             /* the caller sets sizeof(dfm_vk_device_info); the library
                                         writes only that many bytes (see the conventions) */
    VkInstance instance;              /* the renderer's or the host's instance */
    VkPhysicalDevice physical_device; /* the device's physical device */
    VkDevice device;                  /* Vulkan 1.3 */
    uint32_t queue_family;            /* the family of `queue` */
    VkQueue queue;                    /* the queue the renderer submits on */
    uint32_t frames_in_flight;        /* frames the renderer keeps in flight */
    uint32_t samples;                 /* its MSAA sample count (1: none); an overlay draws
                                         after the resolve, single-sampled */
} dfm_vk_device_info;

/* Fills *out (the caller's, struct_size set) for any renderer.
 * DFM_ERROR_INVALID_ARGUMENT for NULL; DFM_ERROR_UNSUPPORTED for a larger
 * struct whose unknown bytes are set. Thread-safe. */
DFM_API dfm_result dfm_vk_renderer_get_device(const dfm_vk_renderer* renderer,
                                              dfm_vk_device_info* out);

/* Window renderers: dfm_vk_renderer_present, and then waits for the frame
 * and copies the picture it presented, overlay included, into `rgba`
 * (rgba_size = width * height * 4 bytes of the window's framebuffer, rows
 * top to bottom, RGBA8): a screenshot of the window. When *presented is
 * false (minimised, swapchain just rebuilt) rgba's contents are
 * unspecified. DFM_ERROR_INVALID_ARGUMENT for another size (the message
 * gives the picture's); DFM_ERROR_UNSUPPORTED without a window or on a
 * surface whose images cannot be copied from. Not thread-safe. */
DFM_API dfm_result dfm_vk_renderer_present_and_read(dfm_vk_renderer* renderer,
                                                    const dfm_vk_frame* frame, uint8_t* rgba,
                                                    size_t rgba_size, bool* presented);

/* Host renderers: records the copy of this frame's vertices into the host's
 * command buffer `cmd` (recording, outside any rendering). Each call uses the
 * next of frames_in_flight buffer sets; the host guarantees the GPU finished
 * the command buffer it recorded frames_in_flight calls ago (its usual frame
 * fence). `cmd` stays the host's. DFM_ERROR_UNSUPPORTED on a renderer with its
 * own device. Not thread-safe. */
DFM_API dfm_result dfm_vk_renderer_record_upload(dfm_vk_renderer* renderer, VkCommandBuffer cmd);

/* Host renderers: records the draw into `cmd`, inside the host's dynamic
 * rendering (vkCmdBeginRendering) whose attachments have the desc's formats
 * and samples and whose area is width x height. Sets viewport and scissor;
 * binds our pipelines and buffers (the host rebinds its own afterwards).
 * Call after dfm_vk_renderer_record_upload in the same command buffer.
 * DFM_ERROR_INVALID_ARGUMENT for a bad camera, flags or size, or no upload
 * yet. Not thread-safe. */
DFM_API dfm_result dfm_vk_renderer_record_draw(dfm_vk_renderer* renderer, VkCommandBuffer cmd,
                                               const dfm_vk_frame* frame, uint32_t width,
                                               uint32_t height);

/* The number of warnings and errors the validation layer reported since
 * creation (0 without dfm_vk_renderer_desc.validation, and for host
 * renderers). Thread-safe. */
DFM_API dfm_result dfm_vk_renderer_validation_message_count(const dfm_vk_renderer* renderer,
                                                            uint64_t* out);

/* The MSAA sample count the renderer draws with (1 when the device has none).
 * Not thread-safe. */
DFM_API dfm_result dfm_vk_renderer_sample_count(const dfm_vk_renderer* renderer, uint32_t* out);

/* A camera that frames all of `positions` in a width x height picture, seen
 * from the front (+z), a little from the right and above, y up; *out is the
 * caller's (zeroed on failure). DFM_ERROR_INVALID_ARGUMENT for NULL or an
 * empty size. Thread-safe. */
DFM_API dfm_result dfm_vk_framing_camera(const dfm_vec3_input* positions, uint32_t width,
                                         uint32_t height, dfm_camera* out);

/* Writes width x height RGBA8 pixels (rows top to bottom, rgba_size bytes) as
 * a PNG file. DFM_ERROR_IO when the file cannot be written. Thread-safe. */
DFM_API dfm_result dfm_vk_write_png(const char* path, const uint8_t* rgba, size_t rgba_size,
                                    uint32_t width, uint32_t height);

#ifdef __cplusplus
}
#endif

#endif
