#include "dualform/pick_camera.hpp"

#include <cerrno>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>

namespace dfm::cli {

pick::Camera to_pick_camera(const dfm_camera& c) {
    return pick::Camera{{c.eye[0], c.eye[1], c.eye[2]},
                        {c.target[0], c.target[1], c.target[2]},
                        {c.up[0], c.up[1], c.up[2]},
                        c.fov_y_degrees,
                        c.width,
                        c.height};
}

Status read_camera_argument(std::string_view argument, dfm_camera& out) {
    const std::size_t start = argument.find_first_not_of(" \t\r\n");
    if (start != std::string_view::npos && argument[start] == '{') {
        return parse_camera(argument, "--camera", out);
    }
    const std::string path(argument);
    std::ifstream in(path, std::ios::binary);
    if (!in) return Status(Errc::io_error, path + ": cannot open: " + std::strerror(errno));
    std::ostringstream text;
    text << in.rdbuf();
    if (in.bad()) return Status(Errc::io_error, path + ": read failed");
    return parse_camera(text.str(), path, out);
}

}  // namespace dfm::cli
