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

enum class OrderingMethod {
    identity,        // keeps the given order (tests, tiny systems)
    minimum_degree,  // approximate minimum degree (the default)
};

const char* ordering_method_name(OrderingMethod method);

// 0, 1, ..., n − 1.
std::vector<std::uint32_t> identity_ordering(std::size_t n);

// Approximate minimum degree (Amestoy, Davis and Duff) on the quotient
// graph, with element absorption and mass elimination of indistinguishable
// vertices; the result is then postordered, which keeps the fill.
std::vector<std::uint32_t> minimum_degree_ordering(const SymmetricGraph& graph);

// The same ordering kept in 64-bit list positions. minimum_degree_ordering
// uses 32-bit ones, and this only for a graph whose lists do not fit them
// (over about 1.7 billion neighbour entries); tests compare the two.
std::vector<std::uint32_t> minimum_degree_ordering_64(const SymmetricGraph& graph);

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
