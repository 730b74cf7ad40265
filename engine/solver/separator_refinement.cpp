#include <algorithm>
#include <array>
#include <cstdlib>
#include <limits>

#include "solver/vertex_separator.hpp"

namespace dfm::solver::separator {

namespace {

constexpr std::uint32_t absent = std::numeric_limits<std::uint32_t>::max();

// A binary max-heap of vertices keyed by gain, ties to the lower vertex, that
// can update or remove any vertex.
class GainHeap {
public:
    explicit GainHeap(std::size_t n) : position_(n, absent) {}

    bool empty() const { return heap_.empty(); }
    bool contains(std::uint32_t v) const { return position_[v] != absent; }
    std::uint32_t top() const { return heap_.front().vertex; }
    std::int64_t top_gain() const { return heap_.front().gain; }

    void clear() {
        for (const Entry& e : heap_) position_[e.vertex] = absent;
        heap_.clear();
    }

    void insert(std::uint32_t v, std::int64_t gain) {
        position_[v] = static_cast<std::uint32_t>(heap_.size());
        heap_.push_back({gain, v});
        up(heap_.size() - 1);
    }

    void add(std::uint32_t v, std::int64_t delta) {
        const std::size_t p = position_[v];
        heap_[p].gain += delta;
        if (delta > 0) {
            up(p);
        } else {
            down(p);
        }
    }

    void remove(std::uint32_t v) {
        const std::size_t p = position_[v];
        position_[v] = absent;
        const Entry last = heap_.back();
        heap_.pop_back();
        if (p == heap_.size()) return;
        heap_[p] = last;
        position_[last.vertex] = static_cast<std::uint32_t>(p);
        up(p);
        down(position_[last.vertex]);
    }

private:
    struct Entry {
        std::int64_t gain;
        std::uint32_t vertex;
    };

    static bool before(const Entry& a, const Entry& b) {
        return a.gain != b.gain ? a.gain > b.gain : a.vertex < b.vertex;
    }

    void place(std::size_t p, const Entry& e) {
        heap_[p] = e;
        position_[e.vertex] = static_cast<std::uint32_t>(p);
    }

    void up(std::size_t p) {
        const Entry e = heap_[p];
        while (p > 0) {
            const std::size_t parent = (p - 1) / 2;
            if (!before(e, heap_[parent])) break;
            place(p, heap_[parent]);
            p = parent;
        }
        place(p, e);
    }

    void down(std::size_t p) {
        const Entry e = heap_[p];
        for (;;) {
            std::size_t child = 2 * p + 1;
            if (child >= heap_.size()) break;
            if (child + 1 < heap_.size() && before(heap_[child + 1], heap_[child])) ++child;
            if (!before(heap_[child], e)) break;
            place(p, heap_[child]);
            p = child;
        }
        place(p, e);
    }

    std::vector<std::uint32_t> position_;
    std::vector<Entry> heap_;
};

struct Move {
    std::uint32_t vertex;
    std::uint8_t to;
    std::size_t pulled_end;  // its pulled vertices end here in the pulled list
};

// Lexicographic quality of a state: balance violation, separator weight,
// imbalance; lower is better.
struct Score {
    std::int64_t excess;
    std::int64_t separator;
    std::int64_t imbalance;

    bool operator<(const Score& o) const {
        if (excess != o.excess) return excess < o.excess;
        if (separator != o.separator) return separator < o.separator;
        return imbalance < o.imbalance;
    }
};

class Refiner {
public:
    Refiner(const WeightedGraph& graph, std::vector<std::uint8_t>& where, std::int64_t max_side)
        : g_(graph),
          where_(where),
          max_side_(max_side),
          heaps_{GainHeap(graph.size()), GainHeap(graph.size())},
          moved_(graph.size(), 0) {
        for (std::size_t v = 0; v < g_.size(); ++v) weight_[where_[v]] += g_.vertex_weights[v];
    }

    void run() {
        constexpr int max_passes = 4;
        for (int pass = 0; pass < max_passes; ++pass)
            if (!pass_improves()) break;
    }

private:
    Score score() const {
        const std::int64_t heavier = std::max(weight_[0], weight_[1]);
        return {std::max<std::int64_t>(0, heavier - max_side_), weight_[2],
                std::abs(weight_[0] - weight_[1])};
    }

    // The gain of moving separator vertex v to side `to`: its weight leaves
    // the separator, its neighbours on the other side enter it.
    std::int64_t gain(std::uint32_t v, int to) const {
        std::int64_t g = g_.vertex_weights[v];
        for (std::size_t p = g_.offsets[v]; p < g_.offsets[v + 1]; ++p) {
            const std::uint32_t u = g_.neighbors[p];
            if (where_[u] == 1 - to) g -= g_.vertex_weights[u];
        }
        return g;
    }

    void enqueue(std::uint32_t v) {
        heaps_[0].insert(v, gain(v, 0));
        heaps_[1].insert(v, gain(v, 1));
    }

    bool pass_improves() {
        heaps_[0].clear();
        heaps_[1].clear();
        for (std::uint32_t v = 0; v < g_.size(); ++v) {
            moved_[v] = 0;
            if (where_[v] == in_separator) enqueue(v);
        }
        moves_.clear();
        pulled_.clear();
        const Score start = score();
        Score best = start;
        std::size_t best_moves = 0;
        std::size_t since_best = 0;
        const std::size_t patience = std::clamp<std::size_t>(g_.size() / 20, 25, 200);
        for (;;) {
            const int to = choose_side();
            if (to < 0) break;
            move(heaps_[to].top(), to);
            const Score now = score();
            if (now < best) {
                best = now;
                best_moves = moves_.size();
                since_best = 0;
            } else if (++since_best > patience) {
                break;
            }
        }
        undo_to(best_moves);
        return best < start;
    }

    // The side whose best move gains most among moves that keep the balance
    // (or improve it); -1 when there is none.
    int choose_side() const {
        int chosen = -1;
        for (int to = 0; to < 2; ++to) {
            if (heaps_[to].empty()) continue;
            const std::uint32_t v = heaps_[to].top();
            const std::int64_t after = weight_[to] + g_.vertex_weights[v];
            if (after > max_side_ && after > weight_[1 - to]) continue;
            if (chosen < 0 || heaps_[to].top_gain() > heaps_[chosen].top_gain() ||
                (heaps_[to].top_gain() == heaps_[chosen].top_gain() &&
                 weight_[to] < weight_[chosen]))
                chosen = to;
        }
        return chosen;
    }

    void move(std::uint32_t v, int to) {
        const int other = 1 - to;
        heaps_[0].remove(v);
        heaps_[1].remove(v);
        moved_[v] = 1;
        where_[v] = static_cast<std::uint8_t>(to);
        weight_[2] -= g_.vertex_weights[v];
        weight_[to] += g_.vertex_weights[v];
        for (std::size_t p = g_.offsets[v]; p < g_.offsets[v + 1]; ++p) {
            const std::uint32_t x = g_.neighbors[p];
            // x now has one more neighbour on v's new side.
            if (where_[x] == in_separator && heaps_[other].contains(x))
                heaps_[other].add(x, -g_.vertex_weights[v]);
        }
        for (std::size_t p = g_.offsets[v]; p < g_.offsets[v + 1]; ++p) {
            const std::uint32_t u = g_.neighbors[p];
            if (where_[u] != other) continue;
            where_[u] = in_separator;
            weight_[other] -= g_.vertex_weights[u];
            weight_[2] += g_.vertex_weights[u];
            pulled_.push_back(u);
            for (std::size_t q = g_.offsets[u]; q < g_.offsets[u + 1]; ++q) {
                const std::uint32_t x = g_.neighbors[q];
                // x lost a neighbour on the other side.
                if (where_[x] == in_separator && x != u && heaps_[to].contains(x))
                    heaps_[to].add(x, g_.vertex_weights[u]);
            }
            if (!moved_[u]) enqueue(u);
        }
        moves_.push_back({v, static_cast<std::uint8_t>(to), pulled_.size()});
    }

    void undo_to(std::size_t keep) {
        while (moves_.size() > keep) {
            const Move m = moves_.back();
            moves_.pop_back();
            const std::size_t pulled_begin = moves_.empty() ? 0 : moves_.back().pulled_end;
            const int other = 1 - m.to;
            for (std::size_t p = pulled_begin; p < m.pulled_end; ++p) {
                const std::uint32_t u = pulled_[p];
                where_[u] = static_cast<std::uint8_t>(other);
                weight_[2] -= g_.vertex_weights[u];
                weight_[other] += g_.vertex_weights[u];
            }
            pulled_.resize(pulled_begin);
            where_[m.vertex] = in_separator;
            weight_[m.to] -= g_.vertex_weights[m.vertex];
            weight_[2] += g_.vertex_weights[m.vertex];
        }
    }

    const WeightedGraph& g_;
    std::vector<std::uint8_t>& where_;
    std::int64_t max_side_;
    std::array<GainHeap, 2> heaps_;
    std::vector<std::uint8_t> moved_;
    std::array<std::int64_t, 3> weight_{0, 0, 0};
    std::vector<Move> moves_;
    std::vector<std::uint32_t> pulled_;
};

}  // namespace

void refine_vertex_separator(const WeightedGraph& graph, std::vector<std::uint8_t>& where,
                             std::int64_t max_side) {
    Refiner(graph, where, max_side).run();
}

}  // namespace dfm::solver::separator
