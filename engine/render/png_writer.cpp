#include "render/png_writer.hpp"

#include <png.h>

#include <cstring>

namespace dfm::render {

Status write_png(const std::string& path, std::span<const std::uint8_t> rgba, std::uint32_t width,
                 std::uint32_t height) {
    if (width == 0 || height == 0) {
        return Status(Errc::invalid_argument, "png: width and height must be positive");
    }
    if (rgba.size() != static_cast<std::size_t>(width) * height * 4) {
        return Status(Errc::invalid_argument, "png: " + std::to_string(rgba.size()) +
                                                  " bytes given for " + std::to_string(width) +
                                                  "x" + std::to_string(height) + " RGBA pixels");
    }
    // libpng's simplified API reports through the struct instead of longjmp,
    // which would skip C++ destructors.
    png_image image;
    std::memset(&image, 0, sizeof image);
    image.version = PNG_IMAGE_VERSION;
    image.width = width;
    image.height = height;
    image.format = PNG_FORMAT_RGBA;
    const int written = png_image_write_to_file(&image, path.c_str(), 0, rgba.data(), 0, nullptr);
    if (!written) {
        const std::string why = image.message;
        png_image_free(&image);
        return Status(Errc::io_error, path + ": cannot write the PNG: " + why);
    }
    return Status::ok();
}

}  // namespace dfm::render
