#include "solver/cholesky_schedule.hpp"

#include <algorithm>

#include "solver/elimination_tree.hpp"

namespace dfm::solver {

CholeskySchedule make_cholesky_schedule(const CholeskySymbolic& sym, std::span<const double> weight,
                                        std::size_t threads) {
    const std::size_t s_count = sym.supernode_count();
    std::vector<double> subtree_work(weight.begin(), weight.end());
    std::vector<std::vector<std::uint32_t>> children(s_count);
    std::vector<std::uint32_t> roots;
    double total = 0.0;
    for (std::uint32_t s = 0; s < s_count; ++s) {
        total += weight[s];
        if (sym.parent[s] == no_parent) {
            roots.push_back(s);
        } else {
            subtree_work[sym.parent[s]] += subtree_work[s];
            children[sym.parent[s]].push_back(s);
        }
    }
    CholeskySchedule schedule;
    schedule.subtrees.resize(threads);
    const double share = total / static_cast<double>(2 * threads);
    const auto heavier = [&](std::uint32_t x, std::uint32_t y) {
        return subtree_work[x] != subtree_work[y] ? subtree_work[x] < subtree_work[y] : x > y;
    };
    std::vector<std::uint32_t> heap = roots;
    std::make_heap(heap.begin(), heap.end(), heavier);
    while (!heap.empty() && subtree_work[heap.front()] > share && !children[heap.front()].empty()) {
        std::pop_heap(heap.begin(), heap.end(), heavier);
        const std::uint32_t s = heap.back();
        heap.pop_back();
        schedule.top.push_back(s);
        for (const std::uint32_t c : children[s]) {
            heap.push_back(c);
            std::push_heap(heap.begin(), heap.end(), heavier);
        }
    }
    std::sort(schedule.top.begin(), schedule.top.end());
    // Longest first, each to the least loaded thread.
    std::sort(heap.begin(), heap.end(),
              [&](std::uint32_t x, std::uint32_t y) { return heavier(y, x); });
    std::vector<double> load(threads, 0.0);
    for (const std::uint32_t root : heap) {
        const std::size_t t =
            static_cast<std::size_t>(std::min_element(load.begin(), load.end()) - load.begin());
        load[t] += subtree_work[root];
        schedule.subtrees[t].push_back(root);
    }
    for (auto& list : schedule.subtrees) std::sort(list.begin(), list.end());
    return schedule;
}

std::vector<double> solve_weights(const CholeskySymbolic& sym) {
    std::vector<double> weight(sym.supernode_count());
    for (std::size_t s = 0; s < weight.size(); ++s)
        weight[s] = static_cast<double>(sym.value_begin[s + 1] - sym.value_begin[s]);
    return weight;
}

}  // namespace dfm::solver
