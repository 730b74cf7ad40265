#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "dualform/dualform.h"

// The gameplay side of the sample: which parts of the model move and how.
// Each "rig" is one edit session with one handle group, animated by a
// function of time; the host never reaches into the SDK beyond dualform.h.
namespace game {

enum class Motion { step, shake, wave };

struct Rig {
    std::string name;
    Motion motion = Motion::wave;
    dfm_roi* roi = nullptr;
    dfm_session* session = nullptr;
    std::uint64_t shown = 0;        // generation on screen
    std::vector<int> submitted_at;  // frame of each generation (index = generation)
};

// Sets up the rigs for `model`: on the cow its tail (shaking) and its front
// leg (stepping); on any other model one wave of its farthest extremity.
// Returns false with a message on stderr when the SDK refuses.
bool make_rigs(dfm_mesh* mesh, const std::string& model, std::vector<Rig>& out);

// The handle group's transform at time t seconds (column-major 4x4).
void transform_at(Motion motion, double t, double diagonal, double out[16]);

void destroy_rigs(std::vector<Rig>& rigs);

}  // namespace game
