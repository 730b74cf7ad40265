#include "dualform/pick_camera.hpp"

namespace dfm::cli {

pick::Camera to_pick_camera(const dfm_camera& c) {
    return pick::Camera{{c.eye[0], c.eye[1], c.eye[2]},
                        {c.target[0], c.target[1], c.target[2]},
                        {c.up[0], c.up[1], c.up[2]},
                        c.fov_y_degrees,
                        c.width,
                        c.height};
}

}  // namespace dfm::cli
