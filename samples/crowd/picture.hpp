#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "dualform/dualform.h"
#include "herd.hpp"

// The whole crowd as one mesh for the renderer: each cow a copy of the mesh
// on a square grid, its animated limb marked, its region's positions taken
// from the newest frame of its session.
class Picture {
public:
    // Lays the cows out; false with a message on stderr when the SDK refuses.
    bool lay_out(dfm_mesh* mesh, const herd::Regions& regions, const std::vector<herd::Cow>& cows);
    // Puts a frame's region into cow `cow`'s copy.
    void place(std::size_t cow, const dfm_frame_view& view);
    // Draws the crowd offscreen and writes the picture to `path` (PNG).
    bool write_png(const char* path, int width, int height, bool validation) const;

private:
    std::size_t vertices_per_cow_ = 0;
    std::vector<float> positions_;  // x y z of every copy's vertices
    std::vector<float> offsets_;    // x y z each cow's copy is moved by
    std::vector<std::uint32_t> indices_;
    std::vector<std::uint8_t> marks_;
};
