#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

// Multilevel vertex separators for nested dissection (internal to the
// ordering code).
namespace dfm::solver::separator {

// An undirected graph with vertex and edge weights, neighbours in CSR form.
struct WeightedGraph {
    std::vector<std::size_t> offsets{0};
    std::vector<std::uint32_t> neighbors;
    std::vector<std::int64_t> edge_weights;    // parallel to neighbors
    std::vector<std::int64_t> vertex_weights;  // one per vertex

    std::size_t size() const { return offsets.size() - 1; }
};

// Which part a vertex lies in.
enum Side : std::uint8_t { side_a = 0, side_b = 1, in_separator = 2 };

// Splits `graph` into A, B and a separator S such that no edge joins A and
// B, S is small and A and B have similar weights: coarsening by heavy-edge
// matching, region growing on the coarsest graph, and Fiduccia–Mattheyses
// refinement on the way back. `where` receives a Side per vertex.
// Deterministic.
void find_vertex_separator(const WeightedGraph& graph, std::vector<std::uint8_t>& where);

// Fiduccia–Mattheyses passes that move separator vertices to a side (pulling
// that vertex's neighbours on the other side into the separator) while the
// separator's weight falls, keeping each side within `max_side` unless a
// move improves the balance. `where` must describe a valid separator.
void refine_vertex_separator(const WeightedGraph& graph, std::vector<std::uint8_t>& where,
                             std::int64_t max_side);

}  // namespace dfm::solver::separator
