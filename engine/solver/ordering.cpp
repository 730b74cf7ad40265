#include "solver/ordering.hpp"

#include <numeric>

namespace dfm::solver {

const char* ordering_method_name(OrderingMethod method) {
    switch (method) {
        case OrderingMethod::identity: return "identity";
        case OrderingMethod::minimum_degree: return "minimum degree";
    }
    return "unknown";
}

std::vector<std::uint32_t> identity_ordering(std::size_t n) {
    std::vector<std::uint32_t> perm(n);
    std::iota(perm.begin(), perm.end(), 0u);
    return perm;
}

std::vector<std::uint32_t> fill_reducing_ordering(const CsrMatrix& a, OrderingMethod method) {
    if (method == OrderingMethod::identity) return identity_ordering(a.rows);
    return fill_reducing_ordering(symmetric_graph(a), method);
}

std::vector<std::uint32_t> fill_reducing_ordering(const SymmetricGraph& graph,
                                                  OrderingMethod method) {
    switch (method) {
        case OrderingMethod::identity: break;
        case OrderingMethod::minimum_degree: return minimum_degree_ordering(graph);
    }
    return identity_ordering(graph.size());
}

bool is_permutation(std::span<const std::uint32_t> perm, std::size_t n) {
    if (perm.size() != n) return false;
    std::vector<bool> seen(n, false);
    for (const std::uint32_t v : perm) {
        if (v >= n || seen[v]) return false;
        seen[v] = true;
    }
    return true;
}

std::vector<std::uint32_t> inverse_permutation(std::span<const std::uint32_t> perm) {
    std::vector<std::uint32_t> inverse(perm.size());
    for (std::size_t i = 0; i < perm.size(); ++i) inverse[perm[i]] = static_cast<std::uint32_t>(i);
    return inverse;
}

}  // namespace dfm::solver
