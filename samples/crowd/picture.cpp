#include "picture.hpp"

#include <cmath>
#include <cstdio>

#include "dualform/dualform_vulkan.h"

namespace {

bool ok(dfm_result result, const char* call) {
    if (result == DFM_OK) return true;
    std::fprintf(stderr, "crowd: %s: %s: %s\n", call, dfm_result_name(result),
                 dfm_last_error_message());
    return false;
}

std::vector<std::uint32_t> region_of(const dfm_roi* roi) {
    std::size_t count = 0;
    dfm_roi_count(roi, &count);
    std::vector<std::uint32_t> vertices(count);
    dfm_roi_read(roi, vertices.data(), count);
    return vertices;
}

}  // namespace

bool Picture::lay_out(dfm_mesh* mesh, const herd::Regions& regions,
                      const std::vector<herd::Cow>& cows) {
    dfm_mesh_info info = {};
    if (!ok(dfm_mesh_get_info(mesh, &info), "dfm_mesh_get_info")) return false;
    const std::size_t n = info.vertex_count;
    vertices_per_cow_ = n;
    std::vector<float> rest(3 * n);
    std::vector<std::uint32_t> triangles(3 * info.triangle_count);
    const dfm_vec3_output out = {rest.data(), n, 0, DFM_SCALAR_FLOAT32};
    if (!ok(dfm_mesh_read_positions(mesh, &out), "dfm_mesh_read_positions") ||
        !ok(dfm_mesh_read_indices(mesh, triangles.data(), triangles.size()),
            "dfm_mesh_read_indices")) {
        return false;
    }
    const std::vector<std::uint32_t> tail = region_of(regions.tail);
    const std::vector<std::uint32_t> leg = region_of(regions.leg);
    // A square grid in the ground plane (x, z), a little wider than a cow.
    const std::size_t columns =
        static_cast<std::size_t>(std::ceil(std::sqrt(static_cast<double>(cows.size()))));
    const double spacing_x = 1.1 * (info.bounds_max[0] - info.bounds_min[0]);
    const double spacing_z = 1.1 * (info.bounds_max[2] - info.bounds_min[2]);
    positions_.clear();
    offsets_.clear();
    indices_.clear();
    marks_.clear();
    for (std::size_t c = 0; c < cows.size(); ++c) {
        const float dx = static_cast<float>(spacing_x * static_cast<double>(c % columns));
        const float dz = static_cast<float>(spacing_z * static_cast<double>(c / columns));
        offsets_.insert(offsets_.end(), {dx, 0.0f, dz});
        for (std::size_t v = 0; v < n; ++v) {
            positions_.insert(positions_.end(),
                              {rest[3 * v] + dx, rest[3 * v + 1], rest[3 * v + 2] + dz});
        }
        const auto first = static_cast<std::uint32_t>(c * n);
        for (std::uint32_t corner : triangles) indices_.push_back(first + corner);
        marks_.resize(marks_.size() + n, DFM_VK_MARK_SURFACE);
        for (std::uint32_t v : cows[c].limb == herd::Limb::tail ? tail : leg) {
            marks_[c * n + v] = DFM_VK_MARK_ROI;
        }
    }
    return true;
}

void Picture::place(std::size_t cow, const dfm_frame_view& view) {
    float* copy = &positions_[3 * cow * vertices_per_cow_];
    const float* offset = &offsets_[3 * cow];
    for (std::size_t i = 0; i < view.roi_count; ++i) {
        for (int c = 0; c < 3; ++c) {
            copy[3 * view.roi_vertices[i] + c] = view.roi_positions[3 * i + c] + offset[c];
        }
    }
}

bool Picture::write_png(const char* path, int width, int height, bool validation) const {
    dfm_vk_renderer_desc desc = {};
    desc.validation = validation;
    dfm_vk_renderer* renderer = nullptr;
    if (!ok(dfm_vk_renderer_create_headless(&desc, &renderer), "create_headless")) return false;
    const std::size_t count = positions_.size() / 3;
    const dfm_vec3_input positions = {positions_.data(), count, 0, DFM_SCALAR_FLOAT32};
    dfm_vk_frame frame = {};
    std::vector<std::uint8_t> rgba(static_cast<std::size_t>(width) * height * 4);
    std::uint64_t messages = 0;
    const bool drawn =
        ok(dfm_vk_renderer_set_mesh(renderer, &positions, indices_.data(), indices_.size() / 3),
           "set_mesh") &&
        ok(dfm_vk_renderer_set_marks(renderer, marks_.data(), marks_.size()), "set_marks") &&
        ok(dfm_vk_framing_camera(&positions, width, height, &frame.camera), "framing_camera") &&
        ok(dfm_vk_renderer_render_offscreen(renderer, &frame, rgba.data(), rgba.size()),
           "render_offscreen") &&
        ok(dfm_vk_write_png(path, rgba.data(), rgba.size(), width, height), "write_png") &&
        ok(dfm_vk_renderer_validation_message_count(renderer, &messages), "message_count");
    dfm_vk_renderer_destroy(renderer);
    if (drawn && messages > 0) {
        std::fprintf(stderr, "crowd: %llu Vulkan validation messages\n",
                     static_cast<unsigned long long>(messages));
        return false;
    }
    return drawn;
}
