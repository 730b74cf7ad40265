#include "surface_match.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <map>
#include <set>

namespace dfm::test::gltf {

namespace {

using Point = std::array<double, 3>;
using Corners = std::array<std::uint32_t, 3>;

constexpr std::uint32_t unknown = UINT32_MAX;

Point point(const std::vector<double>& p, std::uint32_t v) {
    return {p[3 * v], p[3 * v + 1], p[3 * v + 2]};
}

Corners sorted(Corners c) {
    std::sort(c.begin(), c.end());
    return c;
}

}  // namespace

std::vector<std::uint32_t> match_surface(const Surface& split, const Surface& welded) {
    std::map<Point, std::vector<std::uint32_t>> at;
    for (std::uint32_t v = 0; v < welded.positions.size() / 3; ++v)
        at[point(welded.positions, v)].push_back(v);
    std::set<Corners> faces;
    for (std::size_t t = 0; t + 2 < welded.triangles.size(); t += 3)
        faces.insert(
            sorted({welded.triangles[t], welded.triangles[t + 1], welded.triangles[t + 2]}));

    const std::size_t n = split.positions.size() / 3;
    std::vector<std::uint32_t> out(n, unknown);
    std::vector<const std::vector<std::uint32_t>*> candidates(n);
    for (std::uint32_t v = 0; v < n; ++v) {
        const auto it = at.find(point(split.positions, v));
        REQUIRE_MESSAGE(it != at.end(), "split vertex " << v << " is at no welded position");
        candidates[v] = &it->second;
        if (it->second.size() == 1) out[v] = it->second[0];
    }
    // A shared position is told apart by a triangle whose other corners are known.
    for (bool changed = true; changed;) {
        changed = false;
        for (std::size_t t = 0; t + 2 < split.triangles.size(); t += 3) {
            for (int k = 0; k < 3; ++k) {
                const std::uint32_t v = split.triangles[t + k];
                const std::uint32_t a = out[split.triangles[t + (k + 1) % 3]];
                const std::uint32_t b = out[split.triangles[t + (k + 2) % 3]];
                if (out[v] != unknown || a == unknown || b == unknown) continue;
                for (std::uint32_t c : *candidates[v]) {
                    if (!faces.count(sorted({c, a, b}))) continue;
                    REQUIRE_MESSAGE(out[v] == unknown, "split vertex " << v << " is ambiguous");
                    out[v] = c;
                    changed = true;
                }
            }
        }
    }
    for (std::uint32_t v = 0; v < n; ++v)
        REQUIRE_MESSAGE(out[v] != unknown, "split vertex " << v << " matches no welded vertex");
    return out;
}

std::uint32_t vertex_at(const std::vector<double>& positions, const double p[3]) {
    for (std::uint32_t v = 0; v < positions.size() / 3; ++v)
        if (positions[3 * v] == p[0] && positions[3 * v + 1] == p[1] &&
            positions[3 * v + 2] == p[2])
            return v;
    FAIL("no vertex at (" << p[0] << ", " << p[1] << ", " << p[2] << ")");
    return 0;
}

}  // namespace dfm::test::gltf
