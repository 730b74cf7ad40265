#include "mesh/seam_weld.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <tuple>
#include <unordered_map>

namespace dfm::mesh {

namespace {

struct DisjointSets {
    std::vector<std::uint32_t> parent;

    explicit DisjointSets(std::size_t n) : parent(n) {
        std::iota(parent.begin(), parent.end(), std::uint32_t{0});
    }
    std::uint32_t find(std::uint32_t x) {
        while (parent[x] != x) {
            parent[x] = parent[parent[x]];
            x = parent[x];
        }
        return x;
    }
    void join(std::uint32_t a, std::uint32_t b) {
        a = find(a);
        b = find(b);
        if (a != b) parent[std::max(a, b)] = std::min(a, b);
    }
};

// One class per position: bit-identical positions share one.
std::vector<std::uint32_t> exact_classes(std::span<const glm::dvec3> p) {
    std::vector<std::uint32_t> order(p.size());
    std::iota(order.begin(), order.end(), std::uint32_t{0});
    const auto key = [&](std::uint32_t v) { return std::tie(p[v].x, p[v].y, p[v].z); };
    std::sort(order.begin(), order.end(),
              [&](std::uint32_t a, std::uint32_t b) { return key(a) < key(b); });
    std::vector<std::uint32_t> cls(p.size());
    std::uint32_t next = 0;
    for (std::size_t i = 0; i < order.size(); ++i) {
        if (i > 0 && key(order[i]) != key(order[i - 1])) ++next;
        cls[order[i]] = next;
    }
    return cls;
}

// Positions closer than `tol` share a class (and so, transitively, chains of
// them): a grid of cells `tol` wide finds the neighbours.
std::vector<std::uint32_t> tolerance_classes(std::span<const glm::dvec3> p, double tol) {
    struct CellHash {
        std::size_t operator()(const std::tuple<long long, long long, long long>& c) const {
            const auto [x, y, z] = c;
            return static_cast<std::size_t>(x * 73856093LL ^ y * 19349663LL ^ z * 83492791LL);
        }
    };
    const auto cell_of = [&](const glm::dvec3& q) {
        return std::make_tuple(static_cast<long long>(std::floor(q.x / tol)),
                               static_cast<long long>(std::floor(q.y / tol)),
                               static_cast<long long>(std::floor(q.z / tol)));
    };
    std::unordered_map<std::tuple<long long, long long, long long>, std::vector<std::uint32_t>,
                       CellHash>
        cells;
    for (std::uint32_t v = 0; v < p.size(); ++v) cells[cell_of(p[v])].push_back(v);
    DisjointSets sets(p.size());
    for (std::uint32_t v = 0; v < p.size(); ++v) {
        const auto [cx, cy, cz] = cell_of(p[v]);
        for (long long dx = -1; dx <= 1; ++dx) {
            for (long long dy = -1; dy <= 1; ++dy) {
                for (long long dz = -1; dz <= 1; ++dz) {
                    const auto it = cells.find({cx + dx, cy + dy, cz + dz});
                    if (it == cells.end()) continue;
                    for (std::uint32_t w : it->second) {
                        const glm::dvec3 d = p[v] - p[w];
                        if (w < v && d.x * d.x + d.y * d.y + d.z * d.z <= tol * tol) {
                            sets.join(v, w);
                        }
                    }
                }
            }
        }
    }
    std::vector<std::uint32_t> cls(p.size());
    for (std::uint32_t v = 0; v < p.size(); ++v) cls[v] = sets.find(v);
    return cls;
}

// Splits each position class by the vertices' attribute classes; returns
// whether any split. Ties in the position class meet in the sort, so each
// class is one run of `order`.
bool refine_classes(std::vector<std::uint32_t>& cls, std::span<const std::uint32_t> attributes) {
    std::vector<std::uint32_t> order(cls.size());
    std::iota(order.begin(), order.end(), std::uint32_t{0});
    std::sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) {
        return std::tie(cls[a], attributes[a]) < std::tie(cls[b], attributes[b]);
    });
    std::vector<std::uint32_t> refined(cls.size());
    std::uint32_t next = 0;
    bool split = false;
    for (std::size_t begin = 0; begin < order.size();) {
        std::size_t end = begin + 1;
        while (end < order.size() && cls[order[end]] == cls[order[begin]]) ++end;
        for (std::size_t i = begin; i < end; ++i) {
            if (i > begin && attributes[order[i]] != attributes[order[i - 1]]) ++next;
            refined[order[i]] = next;
        }
        if (attributes[order[begin]] != attributes[order[end - 1]]) split = true;
        ++next;
        begin = end;
    }
    cls = std::move(refined);
    return split;
}

// A face's edge between two position classes, lo < hi, with the host
// vertices the face uses at each end.
struct FaceEdge {
    std::uint32_t lo, hi;
    std::uint32_t host_lo, host_hi;
};

// Every face's edge between two position classes, sorted so that the
// faces on one geometric edge lie together.
std::vector<FaceEdge> geometric_edges(std::span<const Triangle> host_triangles,
                                      const std::vector<std::uint32_t>& cls) {
    std::vector<FaceEdge> edges;
    edges.reserve(3 * host_triangles.size());
    for (const Triangle& t : host_triangles) {
        for (int c = 0; c < 3; ++c) {
            const std::uint32_t a = t[c];
            const std::uint32_t b = t[(c + 1) % 3];
            if (cls[a] == cls[b]) continue;
            edges.push_back(cls[a] < cls[b] ? FaceEdge{cls[a], cls[b], a, b}
                                            : FaceEdge{cls[b], cls[a], b, a});
        }
    }
    std::sort(edges.begin(), edges.end(), [](const FaceEdge& x, const FaceEdge& y) {
        return std::tie(x.lo, x.hi) < std::tie(y.lo, y.hi);
    });
    return edges;
}

// Calls `pair(first, second)` for the two faces' edges of every geometric
// edge that exactly two faces use: the two sides of one surface edge. More
// would be a non-manifold edge, left split.
template <class Pair>
void for_each_surface_edge(const std::vector<FaceEdge>& edges, Pair&& pair) {
    for (std::size_t i = 0; i < edges.size();) {
        std::size_t j = i + 1;
        while (j < edges.size() && edges[j].lo == edges[i].lo && edges[j].hi == edges[i].hi) {
            ++j;
        }
        if (j - i == 2) pair(edges[i], edges[i + 1]);
        i = j;
    }
}

// Joins the copies at the two ends of every surface edge.
void join_copies(std::span<const Triangle> host_triangles, const std::vector<std::uint32_t>& cls,
                 DisjointSets& copies) {
    for_each_surface_edge(geometric_edges(host_triangles, cls),
                          [&](const FaceEdge& a, const FaceEdge& b) {
                              copies.join(a.host_lo, b.host_lo);
                              copies.join(a.host_hi, b.host_hi);
                          });
}

// The positions where a surface edge (by position alone) has copies whose
// attribute classes differ at an end: the seams the attributes keep open.
std::size_t count_kept_apart(std::span<const Triangle> host_triangles,
                             const std::vector<std::uint32_t>& by_position,
                             std::span<const std::uint32_t> attributes) {
    std::vector<bool> open(by_position.size(), false);
    for_each_surface_edge(geometric_edges(host_triangles, by_position),
                          [&](const FaceEdge& a, const FaceEdge& b) {
                              if (attributes[a.host_lo] != attributes[b.host_lo]) open[a.lo] = true;
                              if (attributes[a.host_hi] != attributes[b.host_hi]) open[a.hi] = true;
                          });
    return static_cast<std::size_t>(std::count(open.begin(), open.end(), true));
}

}  // namespace

void weld_seams(std::span<const glm::dvec3> host_positions,
                std::span<const Triangle> host_triangles, const WeldOptions& options, Mesh& surface,
                SeamWeld& weld, std::span<const std::uint32_t> classes) {
    const std::size_t n = host_positions.size();
    DisjointSets copies(n);
    std::size_t kept_apart = 0;
    if (options.mode != WeldMode::none) {
        std::vector<std::uint32_t> cls =
            options.mode == WeldMode::tolerance && options.tolerance > 0.0
                ? tolerance_classes(host_positions, options.tolerance)
                : exact_classes(host_positions);
        if (!classes.empty()) {
            const std::vector<std::uint32_t> by_position = cls;
            if (refine_classes(cls, classes)) {
                kept_apart = count_kept_apart(host_triangles, by_position, classes);
            }
        }
        join_copies(host_triangles, cls, copies);
    }

    weld = SeamWeld{};
    weld.kept_apart = kept_apart;
    weld.surface_of.assign(n, no_index);
    std::vector<std::uint32_t> surface_of_root(n, no_index);
    std::uint32_t surfaces = 0;
    for (std::uint32_t v = 0; v < n; ++v) {
        const std::uint32_t root = copies.find(v);
        if (surface_of_root[root] == no_index) surface_of_root[root] = surfaces++;
        weld.surface_of[v] = surface_of_root[root];
    }
    weld.copy_offsets.assign(surfaces + 1, 0);
    for (std::uint32_t s : weld.surface_of) ++weld.copy_offsets[s + 1];
    for (std::size_t s = 0; s < surfaces; ++s) weld.copy_offsets[s + 1] += weld.copy_offsets[s];
    weld.copies.resize(n);
    std::vector<std::uint32_t> fill(weld.copy_offsets.begin(), weld.copy_offsets.end() - 1);
    for (std::uint32_t v = 0; v < n; ++v) weld.copies[fill[weld.surface_of[v]]++] = v;

    surface = Mesh{};
    surface.positions.resize(surfaces);
    for (std::uint32_t s = 0; s < surfaces; ++s) {
        surface.positions[s] = host_positions[weld.lowest_copy(s)];
    }
    weld.host_triangles.assign(host_triangles.begin(), host_triangles.end());
    surface.triangles.reserve(host_triangles.size());
    weld.host_face_of.reserve(host_triangles.size());
    for (std::size_t t = 0; t < host_triangles.size(); ++t) {
        Triangle s;
        for (int c = 0; c < 3; ++c) s[c] = weld.surface_of[host_triangles[t][c]];
        if (s[0] == s[1] || s[1] == s[2] || s[0] == s[2]) continue;
        surface.triangles.push_back(s);
        weld.host_face_of.push_back(static_cast<std::uint32_t>(t));
    }
}

}  // namespace dfm::mesh
