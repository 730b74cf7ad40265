#include "test_system.hpp"

#include <algorithm>
#include <map>
#include <numeric>
#include <utility>

#include "mesh/adjacency.hpp"

namespace dfm::solver_bench {

mesh::Mesh subdivide_midpoint(const mesh::Mesh& mesh) {
    mesh::Mesh out;
    out.positions = mesh.positions;
    std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> midpoint;
    const auto split = [&](std::uint32_t a, std::uint32_t b) {
        const auto key = std::minmax(a, b);
        const auto [it, added] =
            midpoint.try_emplace(key, static_cast<std::uint32_t>(out.positions.size()));
        if (added) out.positions.push_back(0.5 * (mesh.positions[a] + mesh.positions[b]));
        return it->second;
    };
    for (const mesh::Triangle& t : mesh.triangles) {
        const std::uint32_t ab = split(t[0], t[1]);
        const std::uint32_t bc = split(t[1], t[2]);
        const std::uint32_t ca = split(t[2], t[0]);
        out.triangles.push_back({t[0], ab, ca});
        out.triangles.push_back({ab, t[1], bc});
        out.triangles.push_back({ca, bc, t[2]});
        out.triangles.push_back({ab, bc, ca});
    }
    return out;
}

TestSystem make_test_system(const mesh::Mesh& mesh) {
    const std::size_t n = mesh.vertex_count();
    const mesh::VertexAdjacency adjacency = mesh::build_vertex_adjacency(mesh);
    TestSystem system;
    system.diagonal = mesh::compute_bounds(mesh.positions).diagonal();

    std::vector<std::size_t> by_height(n);
    std::iota(by_height.begin(), by_height.end(), std::size_t{0});
    std::stable_sort(by_height.begin(), by_height.end(), [&](std::size_t a, std::size_t b) {
        return mesh.positions[a].y < mesh.positions[b].y;
    });
    const std::size_t band = std::max<std::size_t>(1, n / 20);
    system.handle_weight.assign(n, 0.0);
    for (std::size_t t = 0; t < band; ++t) {
        system.handle_weight[by_height[t]] = 1.0;
        system.handle_weight[by_height[n - 1 - t]] = 1.0;
        system.moving.push_back(by_height[n - 1 - t]);
    }
    std::sort(system.moving.begin(), system.moving.end());

    // LᵀL is the sum over rows i of L of the outer product of row i.
    std::vector<solver::Triplet> triplets;
    std::vector<std::pair<std::uint32_t, double>> row;
    for (std::uint32_t i = 0; i < n; ++i) {
        const auto neighbors = adjacency.of(i);
        row.assign(1, {i, static_cast<double>(neighbors.size())});
        for (const std::uint32_t j : neighbors) row.emplace_back(j, -1.0);
        for (const auto& [a, va] : row)
            for (const auto& [b, vb] : row) triplets.push_back({a, b, va * vb});
        triplets.push_back({i, i, system.handle_weight[i] + 1e-8});
    }
    system.matrix = solver::csr_from_triplets(n, n, triplets);
    return system;
}

}  // namespace dfm::solver_bench
