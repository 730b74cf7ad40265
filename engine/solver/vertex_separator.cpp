#include <algorithm>
#include <array>
#include <cstdlib>
#include <limits>

#include "solver/vertex_separator.hpp"

namespace dfm::solver::separator {

namespace {

constexpr std::uint32_t unmatched = std::numeric_limits<std::uint32_t>::max();
// Coarsening stops at this many vertices, or when a level shrinks too little.
constexpr std::size_t coarsest_size = 120;
constexpr double least_shrink = 0.85;
constexpr int initial_tries = 6;

// SplitMix64: the same sequence on every platform, so orderings are
// reproducible.
class Random {
public:
    explicit Random(std::uint64_t seed) : state_(seed) {}
    std::uint64_t next() {
        std::uint64_t z = (state_ += 0x9e3779b97f4a7c15ull);
        z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
        z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
        return z ^ (z >> 31);
    }
    std::size_t below(std::size_t n) { return static_cast<std::size_t>(next() % n); }

private:
    std::uint64_t state_;
};

std::int64_t total_weight(const WeightedGraph& g) {
    std::int64_t total = 0;
    for (const std::int64_t w : g.vertex_weights) total += w;
    return total;
}

// The heavier side may hold this much of the graph's weight.
std::int64_t side_limit(const WeightedGraph& g) {
    return (total_weight(g) * 3 + 4) / 5;
}

// Heavy-edge matching in a random order; matched pairs become one coarse
// vertex. Caps coarse vertex weights so no vertex swallows the graph.
WeightedGraph coarsen(const WeightedGraph& g, std::vector<std::uint32_t>& coarse_of,
                      Random& random) {
    const std::size_t n = g.size();
    std::vector<std::uint32_t> visit(n);
    for (std::uint32_t v = 0; v < n; ++v) visit[v] = v;
    for (std::size_t i = n; i > 1; --i) std::swap(visit[i - 1], visit[random.below(i)]);
    const std::int64_t max_weight = std::max<std::int64_t>(
        1, (3 * total_weight(g)) / static_cast<std::int64_t>(2 * coarsest_size));
    std::vector<std::uint32_t> match(n, unmatched);
    for (const std::uint32_t v : visit) {
        if (match[v] != unmatched) continue;
        std::uint32_t best = v;
        std::int64_t best_weight = -1;
        for (std::size_t p = g.offsets[v]; p < g.offsets[v + 1]; ++p) {
            const std::uint32_t u = g.neighbors[p];
            if (match[u] != unmatched || g.edge_weights[p] <= best_weight ||
                g.vertex_weights[u] + g.vertex_weights[v] > max_weight)
                continue;
            best = u;
            best_weight = g.edge_weights[p];
        }
        match[v] = best;
        match[best] = v;
    }
    coarse_of.assign(n, 0);
    std::uint32_t coarse_n = 0;
    for (std::uint32_t v = 0; v < n; ++v)
        if (match[v] >= v) coarse_of[v] = coarse_of[match[v]] = coarse_n++;

    WeightedGraph c;
    c.vertex_weights.assign(coarse_n, 0);
    c.offsets.assign(1, 0);
    std::vector<std::uint32_t> slot(coarse_n, unmatched);
    for (std::uint32_t v = 0; v < n; ++v) {
        if (match[v] < v) continue;
        const std::uint32_t cv = coarse_of[v];
        const std::size_t begin = c.neighbors.size();
        const std::uint32_t pair[2] = {v, match[v]};
        for (int t = 0; t < (match[v] == v ? 1 : 2); ++t) {
            const std::uint32_t x = pair[t];
            c.vertex_weights[cv] += g.vertex_weights[x];
            for (std::size_t p = g.offsets[x]; p < g.offsets[x + 1]; ++p) {
                const std::uint32_t cu = coarse_of[g.neighbors[p]];
                if (cu == cv) continue;
                if (slot[cu] == unmatched) {
                    slot[cu] = static_cast<std::uint32_t>(c.neighbors.size());
                    c.neighbors.push_back(cu);
                    c.edge_weights.push_back(g.edge_weights[p]);
                } else {
                    c.edge_weights[slot[cu]] += g.edge_weights[p];
                }
            }
        }
        for (std::size_t p = begin; p < c.neighbors.size(); ++p) slot[c.neighbors[p]] = unmatched;
        c.offsets.push_back(c.neighbors.size());
    }
    return c;
}

// Grows side A breadth-first from `seed` to half the weight; B's vertices
// next to A form the separator.
void grow_region(const WeightedGraph& g, std::uint32_t seed, std::vector<std::uint8_t>& where) {
    const std::size_t n = g.size();
    where.assign(n, side_b);
    std::vector<std::uint8_t> seen(n, 0);
    std::vector<std::uint32_t> queue;
    queue.reserve(n);
    const std::int64_t half = total_weight(g) / 2;
    std::int64_t grown = 0;
    std::size_t head = 0;
    std::uint32_t next_unseen = 0;
    queue.push_back(seed);
    seen[seed] = 1;
    while (grown < half) {
        if (head == queue.size()) {
            while (seen[next_unseen]) ++next_unseen;
            queue.push_back(next_unseen);
            seen[next_unseen] = 1;
        }
        const std::uint32_t v = queue[head++];
        where[v] = side_a;
        grown += g.vertex_weights[v];
        for (std::size_t p = g.offsets[v]; p < g.offsets[v + 1]; ++p) {
            const std::uint32_t u = g.neighbors[p];
            if (!seen[u]) {
                seen[u] = 1;
                queue.push_back(u);
            }
        }
    }
    for (std::uint32_t v = 0; v < n; ++v) {
        if (where[v] != side_b) continue;
        for (std::size_t p = g.offsets[v]; p < g.offsets[v + 1]; ++p) {
            if (where[g.neighbors[p]] == side_a) {
                where[v] = in_separator;
                break;
            }
        }
    }
}

std::array<std::int64_t, 3> part_weights(const WeightedGraph& g,
                                         const std::vector<std::uint8_t>& where) {
    std::array<std::int64_t, 3> w{0, 0, 0};
    for (std::size_t v = 0; v < g.size(); ++v) w[where[v]] += g.vertex_weights[v];
    return w;
}

// The best of a few grown and refined regions: balanced first, then the
// lightest separator.
void initial_separator(const WeightedGraph& g, std::vector<std::uint8_t>& where, Random& random) {
    const std::int64_t limit = side_limit(g);
    std::vector<std::uint8_t> trial;
    std::int64_t best_excess = std::numeric_limits<std::int64_t>::max();
    std::int64_t best_separator = 0;
    for (int t = 0; t < initial_tries; ++t) {
        grow_region(g, static_cast<std::uint32_t>(random.below(g.size())), trial);
        refine_vertex_separator(g, trial, limit);
        const auto w = part_weights(g, trial);
        const std::int64_t excess = std::max<std::int64_t>(0, std::max(w[0], w[1]) - limit);
        if (excess < best_excess || (excess == best_excess && w[2] < best_separator)) {
            best_excess = excess;
            best_separator = w[2];
            where = trial;
        }
    }
}

}  // namespace

void find_vertex_separator(const WeightedGraph& graph, std::vector<std::uint8_t>& where) {
    Random random(0x5eed5eed1234ull + graph.size());
    std::vector<WeightedGraph> levels;
    std::vector<std::vector<std::uint32_t>> coarse_of;
    const WeightedGraph* current = &graph;
    while (current->size() > coarsest_size) {
        std::vector<std::uint32_t> map;
        WeightedGraph coarse = coarsen(*current, map, random);
        if (static_cast<double>(coarse.size()) >
            least_shrink * static_cast<double>(current->size()))
            break;
        levels.push_back(std::move(coarse));
        coarse_of.push_back(std::move(map));
        current = &levels.back();
    }
    std::vector<std::uint8_t> coarse_where;
    initial_separator(*current, coarse_where, random);
    for (std::size_t level = levels.size(); level-- > 0;) {
        const WeightedGraph& fine = level == 0 ? graph : levels[level - 1];
        std::vector<std::uint8_t> fine_where(fine.size());
        for (std::size_t v = 0; v < fine.size(); ++v)
            fine_where[v] = coarse_where[coarse_of[level][v]];
        refine_vertex_separator(fine, fine_where, side_limit(fine));
        coarse_where = std::move(fine_where);
    }
    where = std::move(coarse_where);
}

}  // namespace dfm::solver::separator
