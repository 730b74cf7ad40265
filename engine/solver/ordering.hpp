#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "solver/csr_matrix.hpp"
#include "solver/symmetric_graph.hpp"

namespace dfm::solver {

// Orderings are permutations given as perm[new] = old: the new unknown i is
// the old unknown perm[i]. All are deterministic.

// Measured on vertex 2-ring patterns of real meshes (tools/solver_bench,
// the armadillo and its subdivisions): minimum degree orders about ten
// times faster and gives the least fill at 26k unknowns; nested dissection
// gives 7% less fill at 104k and 17% less at 416k, which shortens the
// numeric factorization by 13% and 25%, far less than its ordering adds.
enum class OrderingMethod {
    identity,           // keeps the given order (tests, tiny systems)
    nested_dissection,  // multilevel vertex separators, recursively
    minimum_degree,     // approximate minimum degree (the default)
};

const char* ordering_method_name(OrderingMethod method);

struct NestedDissectionOptions {
    // Parts of at most this many vertices are not split further; minimum
    // degree orders them.
    std::size_t leaf_size = 256;
};

// 0, 1, ..., n − 1.
std::vector<std::uint32_t> identity_ordering(std::size_t n);

// Nested dissection: each connected part is split by a small vertex
// separator (multilevel: heavy-edge coarsening, region growing on the
// coarsest graph, Fiduccia–Mattheyses refinement on the way back), both
// sides first and the separator last, recursively down to leaves. The
// dissection then constrains a minimum degree ordering of the whole graph
// (every leaf and separator a constraint set, as CHOLMOD does with CAMD), so
// that leaves and separators are ordered knowing their surroundings.
std::vector<std::uint32_t> nested_dissection_ordering(const SymmetricGraph& graph,
                                                      const NestedDissectionOptions& options = {});

// Approximate minimum degree (Amestoy, Davis and Duff) on the quotient
// graph, with element absorption and mass elimination of indistinguishable
// vertices. With `constraints` (one set number per vertex), pivots are
// chosen from set 0 until it is exhausted, then set 1, and so on, each set
// seeing the fill of the ones before (as in CAMD); the result is then
// postordered, which keeps the fill.
std::vector<std::uint32_t> minimum_degree_ordering(const SymmetricGraph& graph,
                                                   std::span<const std::uint32_t> constraints = {});

// The same ordering kept in 64-bit list positions. minimum_degree_ordering
// uses 32-bit ones, and this only for a graph whose lists do not fit them
// (over about 1.7 billion neighbour entries); tests compare the two.
std::vector<std::uint32_t> minimum_degree_ordering_64(
    const SymmetricGraph& graph, std::span<const std::uint32_t> constraints = {});

// The ordering of the pattern of A + Aᵀ by `method`. A must be square.
std::vector<std::uint32_t> fill_reducing_ordering(const CsrMatrix& a, OrderingMethod method);

// The same for a graph already built.
std::vector<std::uint32_t> fill_reducing_ordering(const SymmetricGraph& graph,
                                                  OrderingMethod method);

// True when `perm` holds each of 0 .. n − 1 exactly once.
bool is_permutation(std::span<const std::uint32_t> perm, std::size_t n);

// inverse[perm[i]] = i. `perm` must be a permutation.
std::vector<std::uint32_t> inverse_permutation(std::span<const std::uint32_t> perm);

}  // namespace dfm::solver
