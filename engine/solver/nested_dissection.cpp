#include <algorithm>
#include <limits>

#include "solver/ordering.hpp"
#include "solver/vertex_separator.hpp"

namespace dfm::solver {

namespace {

// A subgraph still to be ordered: the vertices in order[begin, end), which
// are also the positions they will take in the ordering. Its vertices carry
// `label`.
struct Item {
    std::size_t begin;
    std::size_t end;
    std::uint32_t label;
};

class Dissector {
public:
    Dissector(const SymmetricGraph& graph, const NestedDissectionOptions& options)
        : graph_(graph),
          leaf_size_(std::max<std::size_t>(options.leaf_size, 4)),
          order_(identity_ordering(graph.size())),
          label_(graph.size(), 0),
          mark_(graph.size(), 0),
          queue_(graph.size()),
          local_(graph.size(), 0),
          set_of_(graph.size(), 0) {}

    // The constraint set of every vertex: leaves and separators, numbered
    // in the order of their blocks in the dissection's layout, so that every
    // separator comes after both of its sides.
    std::vector<std::uint32_t> run() {
        if (!order_.empty()) stack_.push_back({0, order_.size(), next_label_++});
        while (!stack_.empty()) {
            const Item item = stack_.back();
            stack_.pop_back();
            process(item);
        }
        std::vector<std::uint32_t> rank(block_begin_.size());
        for (std::uint32_t b = 0; b < rank.size(); ++b) rank[b] = b;
        std::sort(rank.begin(), rank.end(), [&](std::uint32_t x, std::uint32_t y) {
            return block_begin_[x] < block_begin_[y];
        });
        std::vector<std::uint32_t> position(rank.size());
        for (std::uint32_t r = 0; r < rank.size(); ++r) position[rank[r]] = r;
        for (std::uint32_t& s : set_of_) s = position[s];
        return std::move(set_of_);
    }

private:
    void process(const Item& item) {
        const std::size_t size = item.end - item.begin;
        if (size <= leaf_size_) {
            close(item.begin, item.end);
            return;
        }
        if (reach(order_[item.begin], item.label, ++stamp_) < size) {
            split_components(item);
            return;
        }
        bisect(item);
    }

    // Breadth-first search from `root` over vertices labelled `label`,
    // leaving the visit order in queue_. Returns the vertices reached.
    std::size_t reach(std::uint32_t root, std::uint32_t label, std::uint32_t stamp) {
        std::size_t head = 0;
        std::size_t tail = 0;
        queue_[tail++] = root;
        mark_[root] = stamp;
        while (head < tail) {
            for (const std::uint32_t u : graph_.of(queue_[head++])) {
                if (label_[u] != label || mark_[u] == stamp) continue;
                mark_[u] = stamp;
                queue_[tail++] = u;
            }
        }
        return tail;
    }

    // Lays out the item's connected components one after another; small ones
    // are grouped into leaves so that many tiny components cost little.
    void split_components(const Item& item) {
        const std::uint32_t stamp = ++stamp_;
        scratch_.clear();
        component_sizes_.clear();
        for (std::size_t p = item.begin; p < item.end; ++p) {
            const std::uint32_t v = order_[p];
            if (mark_[v] == stamp) continue;
            const std::size_t reached = reach(v, item.label, stamp);
            scratch_.insert(scratch_.end(), queue_.begin(),
                            queue_.begin() + static_cast<std::ptrdiff_t>(reached));
            component_sizes_.push_back(reached);
        }
        std::copy(scratch_.begin(), scratch_.end(),
                  order_.begin() + static_cast<std::ptrdiff_t>(item.begin));
        std::size_t group_begin = item.begin;
        std::size_t position = item.begin;
        const auto close_group = [&] {
            if (position == group_begin) return;
            const std::uint32_t label = next_label_++;
            for (std::size_t p = group_begin; p < position; ++p) label_[order_[p]] = label;
            stack_.push_back({group_begin, position, label});
            group_begin = position;
        };
        for (const std::size_t size : component_sizes_) {
            if (position + size - group_begin > leaf_size_) close_group();
            position += size;
        }
        close_group();
    }

    // The item's subgraph with local vertex numbers and unit weights.
    void extract(const Item& item) {
        const std::size_t m = item.end - item.begin;
        for (std::size_t t = 0; t < m; ++t)
            local_[order_[item.begin + t]] = static_cast<std::uint32_t>(t);
        sub_.offsets.assign(1, 0);
        sub_.neighbors.clear();
        for (std::size_t t = 0; t < m; ++t) {
            for (const std::uint32_t u : graph_.of(order_[item.begin + t]))
                if (label_[u] == item.label) sub_.neighbors.push_back(local_[u]);
            sub_.offsets.push_back(sub_.neighbors.size());
        }
        sub_.edge_weights.assign(sub_.neighbors.size(), 1);
        sub_.vertex_weights.assign(m, 1);
    }

    // Splits a connected item by a vertex separator, in place, into side A,
    // side B and the separator, which is ordered last.
    void bisect(const Item& item) {
        extract(item);
        separator::find_vertex_separator(sub_, where_);
        const std::size_t m = item.end - item.begin;
        std::size_t counts[3] = {0, 0, 0};
        for (const std::uint8_t w : where_) ++counts[w];
        if (counts[separator::side_a] == 0 || counts[separator::side_b] == 0) {
            close(item.begin, item.end);
            return;
        }
        scratch_.assign(order_.begin() + static_cast<std::ptrdiff_t>(item.begin),
                        order_.begin() + static_cast<std::ptrdiff_t>(item.end));
        std::size_t next[3] = {item.begin, item.begin + counts[0],
                               item.begin + counts[0] + counts[1]};
        for (std::size_t t = 0; t < m; ++t) order_[next[where_[t]]++] = scratch_[t];
        const std::uint32_t a_label = next_label_++;
        const std::uint32_t b_label = next_label_++;
        const std::size_t a_end = item.begin + counts[0];
        const std::size_t b_end = a_end + counts[1];
        for (std::size_t p = item.begin; p < a_end; ++p) label_[order_[p]] = a_label;
        for (std::size_t p = a_end; p < b_end; ++p) label_[order_[p]] = b_label;
        close(b_end, item.end);
        stack_.push_back({a_end, b_end, b_label});
        stack_.push_back({item.begin, a_end, a_label});
    }

    // The item's vertices become one constraint set, ordered by minimum
    // degree later.
    void close(std::size_t begin, std::size_t end) {
        for (std::size_t p = begin; p < end; ++p) set_of_[order_[p]] = next_set_;
        block_begin_.push_back(begin);
        ++next_set_;
    }

    const SymmetricGraph& graph_;
    std::size_t leaf_size_;
    std::vector<std::uint32_t> order_;
    std::vector<std::uint32_t> label_;
    std::vector<std::uint32_t> mark_;
    std::uint32_t stamp_ = 0;
    std::vector<std::uint32_t> queue_;
    std::vector<std::uint32_t> local_;
    std::vector<Item> stack_;
    std::uint32_t next_label_ = 0;
    std::vector<std::uint32_t> scratch_;
    std::vector<std::size_t> component_sizes_;
    separator::WeightedGraph sub_;
    std::vector<std::uint8_t> where_;
    std::vector<std::uint32_t> set_of_;
    std::vector<std::size_t> block_begin_;
    std::uint32_t next_set_ = 0;
};

}  // namespace

std::vector<std::uint32_t> nested_dissection_ordering(const SymmetricGraph& graph,
                                                      const NestedDissectionOptions& options) {
    const std::vector<std::uint32_t> sets = Dissector(graph, options).run();
    return minimum_degree_ordering(graph, sets);
}

}  // namespace dfm::solver
