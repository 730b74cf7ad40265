#include "support/procedural_meshes.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <utility>

#include <glm/geometric.hpp>

namespace dfm::test {

using mesh::Mesh;
using mesh::Triangle;

Mesh make_icosphere(int subdivisions) {
    const double t = (1.0 + std::sqrt(5.0)) / 2.0;
    Mesh m;
    m.positions = {{-1, t, 0},  {1, t, 0},  {-1, -t, 0}, {1, -t, 0}, {0, -1, t},  {0, 1, t},
                   {0, -1, -t}, {0, 1, -t}, {t, 0, -1},  {t, 0, 1},  {-t, 0, -1}, {-t, 0, 1}};
    m.triangles = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                   {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                   {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                   {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
    for (glm::dvec3& p : m.positions) p = glm::normalize(p);
    for (int s = 0; s < subdivisions; ++s) {
        std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> midpoints;
        auto midpoint = [&](std::uint32_t a, std::uint32_t b) {
            const auto key = std::minmax(a, b);
            auto it = midpoints.find(key);
            if (it != midpoints.end()) return it->second;
            const auto index = static_cast<std::uint32_t>(m.positions.size());
            m.positions.push_back(glm::normalize(m.positions[a] + m.positions[b]));
            midpoints.emplace(key, index);
            return index;
        };
        std::vector<Triangle> next;
        next.reserve(m.triangles.size() * 4);
        for (const Triangle& f : m.triangles) {
            const std::uint32_t ab = midpoint(f[0], f[1]);
            const std::uint32_t bc = midpoint(f[1], f[2]);
            const std::uint32_t ca = midpoint(f[2], f[0]);
            next.push_back({f[0], ab, ca});
            next.push_back({f[1], bc, ab});
            next.push_back({f[2], ca, bc});
            next.push_back({ab, bc, ca});
        }
        m.triangles = std::move(next);
    }
    return m;
}

Mesh make_limb(int segments, int rings, double radius, double length) {
    Mesh m;
    const double pi = std::acos(-1.0);
    m.positions.push_back({0.0, 0.0, 0.0});
    for (int j = 0; j <= rings; ++j) {
        const double y = length * j / rings;
        for (int i = 0; i < segments; ++i) {
            const double a = 2.0 * pi * i / segments;
            m.positions.push_back({radius * std::cos(a), y, radius * std::sin(a)});
        }
    }
    const auto top = static_cast<std::uint32_t>(m.positions.size());
    m.positions.push_back({0.0, length, 0.0});
    auto ring = [&](int j, int i) {
        return static_cast<std::uint32_t>(1 + j * segments + (i % segments));
    };
    for (int i = 0; i < segments; ++i) m.triangles.push_back({0, ring(0, i), ring(0, i + 1)});
    for (int j = 0; j < rings; ++j) {
        for (int i = 0; i < segments; ++i) {
            const std::uint32_t a = ring(j, i);
            const std::uint32_t b = ring(j, i + 1);
            const std::uint32_t c = ring(j + 1, i + 1);
            const std::uint32_t d = ring(j + 1, i);
            m.triangles.push_back({a, d, c});
            m.triangles.push_back({a, c, b});
        }
    }
    for (int i = 0; i < segments; ++i) {
        m.triangles.push_back({top, ring(rings, i + 1), ring(rings, i)});
    }
    return m;
}

Mesh make_grid(int nx, int ny) {
    Mesh m;
    for (int j = 0; j <= ny; ++j) {
        for (int i = 0; i <= nx; ++i) m.positions.push_back({double(i), double(j), 0.0});
    }
    auto at = [&](int i, int j) { return static_cast<std::uint32_t>(j * (nx + 1) + i); };
    for (int j = 0; j < ny; ++j) {
        for (int i = 0; i < nx; ++i) {
            m.triangles.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
            m.triangles.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
        }
    }
    return m;
}

}  // namespace dfm::test
