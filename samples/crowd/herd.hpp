#pragma once

#include <cstdint>
#include <vector>

#include "dualform/dualform.h"

// The gameplay side of the crowd: cows on one mesh, each with one limb (its
// tail or its front leg) that moves on its own. Every cow's limb is a
// session of its own; the regions are Water-Filled once and shared.
namespace herd {

enum class Limb { tail, leg };

// The two regions of the cow and each one's handle vertices.
struct Regions {
    dfm_roi* tail = nullptr;
    dfm_roi* leg = nullptr;
    std::vector<std::uint32_t> tail_handle;
    std::vector<std::uint32_t> leg_handle;
};

struct Cow {
    Limb limb = Limb::tail;
    double phase = 0.0;  // seconds its motion runs ahead of the first cow's
    dfm_session* session = nullptr;
    std::uint64_t shown = 0;        // the newest finished generation picked up
    std::vector<int> submitted_at;  // the tick of each generation (index = generation)
    int last_finished_tick = -1;    // when it last picked up a finished frame
    int longest_wait = 0;           // the most ticks between two finished frames
    int finished = 0;               // finished frames picked up
};

// The regions on the paper's cow ("model:cow"); false with a message on
// stderr when the SDK refuses.
bool make_regions(dfm_mesh* mesh, Regions& out);
void destroy_regions(Regions& regions);

// `count` cows, tails and legs in turn, each with its session.
bool make_cows(dfm_mesh* mesh, const Regions& regions, std::size_t count, std::vector<Cow>& out);
void destroy_cows(std::vector<Cow>& cows);

// The limb's handle transform at time t seconds (column-major 4x4).
void transform_at(const Cow& cow, double t, double diagonal, double out[16]);

}  // namespace herd
