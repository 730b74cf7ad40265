#include "herd.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace herd {

namespace {

constexpr double pi = 3.14159265358979323846;

bool ok(dfm_result result, const char* call) {
    if (result == DFM_OK) return true;
    std::fprintf(stderr, "crowd: %s: %s: %s\n", call, dfm_result_name(result),
                 dfm_last_error_message());
    return false;
}

// The region from `first` up to the plane through `last`, and a ball of
// `radius` diagonals around `first` as its handle.
bool limb_region(dfm_mesh* mesh, std::uint32_t first, std::uint32_t last, double radius,
                 dfm_roi** region, std::vector<std::uint32_t>& handle) {
    dfm_water_fill_diagnosis diagnosis = {};
    if (!ok(dfm_roi_water_fill(mesh, first, last, region, &diagnosis), "dfm_roi_water_fill")) {
        return false;
    }
    if (diagnosis.suspect) {
        std::fprintf(stderr, "crowd: the region %u -> %u looks wrong (%zu loops)\n", first, last,
                     diagnosis.loops);
        return false;
    }
    dfm_roi* ball = nullptr;
    if (!ok(dfm_roi_ball(mesh, first, radius, &ball), "dfm_roi_ball")) return false;
    std::size_t count = 0;
    dfm_roi_count(ball, &count);
    handle.resize(count);
    const bool read = ok(dfm_roi_read(ball, handle.data(), count), "dfm_roi_read");
    dfm_roi_destroy(ball);
    return read;
}

}  // namespace

bool make_regions(dfm_mesh* mesh, Regions& out) {
    // Vertex numbers of the paper's cow: 2334 is the tail tip, 964 up the
    // tail below its root; 771 the front hoof, 681 above the knee.
    return limb_region(mesh, 2334, 964, 0.02, &out.tail, out.tail_handle) &&
           limb_region(mesh, 771, 681, 0.03, &out.leg, out.leg_handle);
}

void destroy_regions(Regions& regions) {
    dfm_roi_destroy(regions.tail);
    dfm_roi_destroy(regions.leg);
    regions = Regions{};
}

bool make_cows(dfm_mesh* mesh, const Regions& regions, std::size_t count, std::vector<Cow>& out) {
    out.assign(count, Cow{});
    for (std::size_t i = 0; i < count; ++i) {
        Cow& cow = out[i];
        cow.limb = i % 2 == 0 ? Limb::tail : Limb::leg;
        cow.phase = 0.37 * static_cast<double>(i);
        cow.submitted_at.push_back(-1);  // generation 0, the rest pose: there before tick 0
        const std::vector<std::uint32_t>& handle =
            cow.limb == Limb::tail ? regions.tail_handle : regions.leg_handle;
        const dfm_handle_group group = {handle.data(), handle.size()};
        dfm_session_desc desc = {};
        desc.struct_size = sizeof desc;
        desc.roi = cow.limb == Limb::tail ? regions.tail : regions.leg;
        desc.groups = &group;
        desc.group_count = 1;
        if (!ok(dfm_session_create(mesh, &desc, &cow.session), "dfm_session_create")) {
            return false;
        }
    }
    return true;
}

void destroy_cows(std::vector<Cow>& cows) {
    for (Cow& cow : cows) dfm_session_destroy(cow.session);
    cows.clear();
}

void transform_at(const Cow& cow, double t, double diagonal, double out[16]) {
    for (int i = 0; i < 16; ++i) out[i] = (i % 5 == 0) ? 1.0 : 0.0;
    const double s = t + cow.phase;
    if (cow.limb == Limb::tail) {  // side to side at 2 Hz, a flick up at 4 Hz
        out[14] = 0.06 * diagonal * std::sin(2.0 * pi * 2.0 * s);
        out[13] = 0.02 * diagonal * std::sin(2.0 * pi * 4.0 * s);
    } else {  // forward and back at 0.75 Hz, lifted on the way out
        out[12] = 0.06 * diagonal * (0.5 - 0.5 * std::cos(2.0 * pi * 0.75 * s));
        out[13] = 0.03 * diagonal * std::max(0.0, std::sin(2.0 * pi * 0.75 * s));
    }
}

}  // namespace herd
