#include "roi/water_fill.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <string>
#include <utility>

#include <glm/geometric.hpp>

namespace dfm::roi {

namespace {

using CutEdge = std::pair<std::uint32_t, std::uint32_t>;  // (region vertex, far vertex)

Status check_index(std::uint32_t v, std::size_t n, const char* what) {
    if (v < n) return Status::ok();
    return Status(Errc::out_of_range, std::string("water_fill: ") + what + " vertex " +
                                          std::to_string(v) + " is out of range (the mesh has " +
                                          std::to_string(n) + " vertices)");
}

Status check_surface(const SurfaceView& s) {
    const std::size_t n = s.positions.size();
    if (!s.neighbors || s.neighbors->offsets.size() != n + 1 ||
        s.vertex_face_offsets.size() != n + 1) {
        return Status(Errc::invalid_argument,
                      "water_fill: the adjacency and vertex-face offsets must have one entry per "
                      "vertex plus one (" +
                          std::to_string(n + 1) + ")");
    }
    return Status::ok();
}

// Union–find with path halving; the loops are its classes.
std::uint32_t find_root(std::vector<std::uint32_t>& parent, std::uint32_t x) {
    while (parent[x] != x) {
        parent[x] = parent[parent[x]];
        x = parent[x];
    }
    return x;
}

// Groups the region's cut edges (sorted) into loops: two cut edges are in one
// loop when a face crosses the plane through both. A face with region and
// non-region vertices holds exactly two cut edges (every non-region
// neighbour of the region is on the far side, or the fill would have taken
// it). Each such face is handled once, from its lowest region vertex, so the
// cost is in the cut, not the region.
std::size_t count_loops(const SurfaceView& s, const std::vector<std::uint8_t>& in_region,
                        const std::vector<CutEdge>& cuts) {
    std::vector<std::uint32_t> parent(cuts.size());
    std::iota(parent.begin(), parent.end(), 0u);
    const auto id = [&](std::uint32_t a, std::uint32_t b) {
        const auto it = std::lower_bound(cuts.begin(), cuts.end(), CutEdge{a, b});
        return static_cast<std::uint32_t>(it - cuts.begin());
    };
    // Only faces around a cut edge's region end can cross the plane.
    for (std::size_t c = 0; c < cuts.size(); ++c) {
        const std::uint32_t a = cuts[c].first;
        if (c > 0 && cuts[c - 1].first == a) continue;
        for (std::uint32_t i = s.vertex_face_offsets[a]; i < s.vertex_face_offsets[a + 1]; ++i) {
            const mesh::Triangle& t = s.triangles[s.vertex_faces[i]];
            std::uint32_t lowest_in = mesh::no_index;
            std::uint32_t found = 0;
            std::uint32_t ids[3] = {0, 0, 0};
            for (int k = 0; k < 3; ++k) {
                if (in_region[t[k]]) lowest_in = std::min(lowest_in, t[k]);
            }
            if (lowest_in != a) continue;
            for (int k = 0; k < 3; ++k) {
                const std::uint32_t x = t[k];
                const std::uint32_t y = t[(k + 1) % 3];
                if (in_region[x] == in_region[y]) continue;
                ids[found++] = in_region[x] ? id(x, y) : id(y, x);
            }
            for (std::uint32_t k = 1; k < found; ++k) {
                parent[find_root(parent, ids[k])] = find_root(parent, ids[0]);
            }
        }
    }
    std::size_t loops = 0;
    for (std::uint32_t i = 0; i < parent.size(); ++i) loops += find_root(parent, i) == i;
    return loops;
}

// Whether the plane–surface loop passing nearest to `last` bounds the
// region. `last` lies on the plane, so when it has a neighbour on the near
// side, a loop passes through `last` itself. A loop's near-side vertices are
// all joined by near-side edges (consecutive cut edges share a face), so the
// loop bounds the region exactly when one of them is in it. Otherwise (last
// is an extreme point along the line) the nearest crossing of any mesh edge
// decides, found by one scan of the mesh.
bool bounded_by_last_loop(const SurfaceView& s, std::uint32_t last,
                          const std::vector<std::uint8_t>& in_region, const auto& side) {
    bool near_neighbor = false;
    for (std::uint32_t u : s.neighbors->of(last)) {
        if (side(u) < 0.0) {
            if (in_region[u]) return true;
            near_neighbor = true;
        }
    }
    if (near_neighbor) return false;
    const glm::dvec3 p = s.positions[last];
    double best = INFINITY;
    bool bounded = false;
    for (std::uint32_t a = 0; a < s.positions.size(); ++a) {
        const double sa = side(a);
        if (!(sa < 0.0)) continue;
        for (std::uint32_t b : s.neighbors->of(a)) {
            const double sb = side(b);
            if (sb < 0.0) continue;
            const double t = sa / (sa - sb);
            const double d =
                glm::length(s.positions[a] + t * (s.positions[b] - s.positions[a]) - p);
            if (d < best) {
                best = d;
                bounded = in_region[a] != 0;
            }
        }
    }
    return bounded;
}

}  // namespace

Status water_fill(const SurfaceView& surface, std::uint32_t first, std::uint32_t last,
                  WaterFill& out) {
    out = WaterFill{};
    const std::size_t n = surface.positions.size();
    if (Status st = check_surface(surface); !st) return st;
    if (Status st = check_index(first, n, "first"); !st) return st;
    if (Status st = check_index(last, n, "last"); !st) return st;
    if (first == last) {
        return Status(Errc::invalid_argument,
                      "water_fill: first and last are the same vertex " + std::to_string(first));
    }
    const glm::dvec3 origin = surface.positions[last];
    const glm::dvec3 line = origin - surface.positions[first];
    const double length = glm::length(line);
    if (!(length > 0.0) || !std::isfinite(length)) {
        return Status(Errc::invalid_argument, "water_fill: vertices " + std::to_string(first) +
                                                  " and " + std::to_string(last) +
                                                  " do not span a region line (same or "
                                                  "non-finite positions)");
    }
    const glm::dvec3 normal = line / length;
    // Signed distance to the cutting plane; a NaN position compares as far.
    const auto side = [&](std::uint32_t v) {
        return glm::dot(surface.positions[v] - origin, normal);
    };

    std::vector<std::uint8_t> in_region(n, 0);
    std::vector<std::uint32_t>& region = out.vertices;
    region.push_back(first);
    in_region[first] = 1;
    std::vector<CutEdge> cuts;
    // Each region vertex is expanded once, so every far neighbour met here
    // is one cut edge, met once.
    for (std::size_t head = 0; head < region.size(); ++head) {
        const std::uint32_t a = region[head];
        for (std::uint32_t b : surface.neighbors->of(a)) {
            if (in_region[b]) continue;
            if (side(b) < 0.0) {
                in_region[b] = 1;
                region.push_back(b);
            } else {
                cuts.emplace_back(a, b);
            }
        }
    }
    std::sort(region.begin(), region.end());
    std::sort(cuts.begin(), cuts.end());

    WaterFillDiagnosis& d = out.diagnosis;
    d.loops = count_loops(surface, in_region, cuts);
    d.bounded_by_last_loop = bounded_by_last_loop(surface, last, in_region, side);
    d.suspect = d.loops != 1 || !d.bounded_by_last_loop || 2 * region.size() > n;
    return Status::ok();
}

}  // namespace dfm::roi
