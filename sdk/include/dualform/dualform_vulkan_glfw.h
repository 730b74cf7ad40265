/*
 * Dualform's renderer in a GLFW window: a small backend over
 * dualform_vulkan.h (libdualform_vulkan_glfw, a static library), kept apart
 * so that a headless host, or one rendering on its own device, links no
 * window system. A host with another window system fills a dfm_vk_window
 * itself and calls dfm_vk_renderer_create_for_window.
 */
#ifndef DUALFORM_DUALFORM_VULKAN_GLFW_H
#define DUALFORM_DUALFORM_VULKAN_GLFW_H

#include "dualform/dualform_vulkan.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Creates a renderer with its own instance and device that presents to a
 * GLFW window (`glfw_window` is a GLFWwindow*, created with
 * GLFW_CLIENT_API = GLFW_NO_API; glfwInit must have succeeded). The window is
 * borrowed and must outlive the renderer. DFM_ERROR_INVALID_ARGUMENT for a
 * NULL window, DFM_ERROR_DEVICE when GLFW cannot make the window's surface
 * (no Vulkan support); other errors and ownership as
 * dfm_vk_renderer_create_headless. Call from the thread that owns the
 * window. */
dfm_result dfm_vk_renderer_create_window(const dfm_vk_renderer_desc* desc, void* glfw_window,
                                         dfm_vk_renderer** out);

#ifdef __cplusplus
}
#endif

#endif
