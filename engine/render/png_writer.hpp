#pragma once

#include <cstdint>
#include <span>
#include <string>

#include "render/vulkan_result.hpp"

namespace dfm::render {

// Writes an 8-bit RGBA picture (rows top to bottom, width × height × 4
// bytes) as a PNG file with libpng.
Status write_png(const std::string& path, std::span<const std::uint8_t> rgba, std::uint32_t width,
                 std::uint32_t height);

}  // namespace dfm::render
