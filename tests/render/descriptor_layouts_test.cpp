#include <doctest/doctest.h>

#include <cstddef>
#include <cstdint>

#include "descriptor_layouts_vulkan.hpp"
#include "dualform/dualform_vulkan.h"
#include "support/layout_checks.hpp"

// The renderer's entries of the C layer's table of what struct_size 0
// stands for (sdk/src/vulkan/descriptor_layouts_vulkan.hpp), against copies
// of the 0.2 layouts: a later version adds fields to the structs, and
// these copies stay as they are.
namespace {
namespace v0_2 {

struct overlay_desc {
    std::uint32_t struct_size;
    dfm_vk_overlay_fn record;
    void* user;
};

struct device_info {
    std::uint32_t struct_size;
    VkInstance instance;
    VkPhysicalDevice physical_device;
    VkDevice device;
    std::uint32_t queue_family;
    VkQueue queue;
    std::uint32_t frames_in_flight;
    std::uint32_t samples;
};

}  // namespace v0_2
}  // namespace

TEST_CASE("renderer descriptors: the library's struct_size 0 is each struct's 0.2 layout") {
    using dfm::sdk::FirstLayout;
    CHECK(FirstLayout<dfm_vk_overlay_desc>::size == DFM_END_OF(v0_2::overlay_desc, user));
    CHECK_SAME_PLACE(v0_2::overlay_desc, dfm_vk_overlay_desc, record);
    CHECK_SAME_PLACE(v0_2::overlay_desc, dfm_vk_overlay_desc, user);

    CHECK(FirstLayout<dfm_vk_device_info>::size == DFM_END_OF(v0_2::device_info, samples));
    CHECK_SAME_PLACE(v0_2::device_info, dfm_vk_device_info, instance);
    CHECK_SAME_PLACE(v0_2::device_info, dfm_vk_device_info, physical_device);
    CHECK_SAME_PLACE(v0_2::device_info, dfm_vk_device_info, device);
    CHECK_SAME_PLACE(v0_2::device_info, dfm_vk_device_info, queue_family);
    CHECK_SAME_PLACE(v0_2::device_info, dfm_vk_device_info, queue);
    CHECK_SAME_PLACE(v0_2::device_info, dfm_vk_device_info, frames_in_flight);
    CHECK_SAME_PLACE(v0_2::device_info, dfm_vk_device_info, samples);
}
