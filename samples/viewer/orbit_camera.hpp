#pragma once

#include <array>

#include "dualform/dualform.h"

namespace viewer {

using Vec3 = std::array<double, 3>;

// A camera orbiting a target point: yaw and pitch around it at a distance.
// It produces the SDK's dfm_camera, so picking and drawing agree with it.
class OrbitCamera {
public:
    // Starts from `start` (a framing camera): same eye, target and field.
    void reset(const dfm_camera& start);
    void set_viewport(int width, int height);

    void orbit(double dx_pixels, double dy_pixels);
    void pan(double dx_pixels, double dy_pixels);
    void zoom(double steps);

    dfm_camera camera() const;

    // The world-space vector a drag of (dx, dy) pixels covers on the plane
    // through `at` facing the viewer.
    Vec3 drag_in_view_plane(const Vec3& at, double dx, double dy) const;
    // The pixel `p` projects to; false when it is behind the eye.
    bool project(const Vec3& p, double& x, double& y) const;
    // The unit vector from the eye toward the target.
    Vec3 forward() const;

private:
    void basis(Vec3& right, Vec3& up, Vec3& fwd) const;

    Vec3 target_{0, 0, 0};
    double yaw_ = 0.0, pitch_ = 0.0, distance_ = 1.0;
    double fov_y_degrees_ = 45.0;
    int width_ = 640, height_ = 480;
};

}  // namespace viewer
