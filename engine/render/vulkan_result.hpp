#pragma once

#include <vulkan/vulkan.h>

#include "core/status.hpp"

namespace dfm::render {

// A failed Vulkan call as a status naming the call and the VkResult; running
// out of host or device memory is reported as such, anything else as a
// device failure (Errc::device).
Status vk_failure(VkResult result, const char* call);

const char* vk_result_name(VkResult result);

}  // namespace dfm::render
