#pragma once

// What struct_size 0 stands for in dualform_vulkan.h's structs that the
// library reads (descriptor_layouts.hpp): their 0.2 layouts, in which they
// appeared. tests/render/descriptor_layouts_test.cpp checks them.

#include "descriptor_layouts.hpp"
#include "dualform/dualform_vulkan.h"

DFM_FIRST_LAYOUT(dfm_vk_overlay_desc, user);
DFM_FIRST_LAYOUT(dfm_vk_device_info, samples);
