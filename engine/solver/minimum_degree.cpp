#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

#include "core/pooled_allocator.hpp"
#include "solver/ordering.hpp"

namespace dfm::solver {

namespace {

// A reference to object j stored where a list pointer would be: "absorbed
// into j" for variables and elements, -1 ("root") for none.
template <class Index>
constexpr Index flip(Index j) {
    return -j - 2;
}

// Approximate minimum degree on the quotient graph (Amestoy, Davis and Duff,
// SIAM J. Matrix Anal. Appl. 17(4), 1996). Variables are the graph's
// vertices; eliminating a pivot turns it into an element whose variable list
// stands for the clique it creates. Each variable's list in `memory_` holds
// first its adjacent elements (node_[i].elements of them), then its adjacent
// variables. node_[i].size is the number of vertices supervariable i stands for.
// Number n is an extra element that collects dense rows, ordered last.
// Positions and numbers are kept in the signed type Index, 32-bit where
// the lists fit: the elimination waits on memory, and halving its working
// set shortens it accordingly.
template <class Index>
class MinimumDegree {
public:
    static constexpr Index none = -1;

    // Whether Index holds every position of a graph with n vertices and
    // `edges` neighbour entries.
    static bool fits(std::size_t n, std::size_t edges) {
        return memory_size(n, edges) < static_cast<std::size_t>(std::numeric_limits<Index>::max());
    }

    explicit MinimumDegree(const SymmetricGraph& graph)
        : n_(static_cast<Index>(graph.size())),
          node_(static_cast<std::size_t>(n_) + 1, Node{}),
          head_(static_cast<std::size_t>(n_) + 1, none),
          hash_head_(static_cast<std::size_t>(n_) + 1, none) {
        memory_.resize(memory_size(graph.size(), graph.neighbors.size()));
        const std::size_t edges = graph.neighbors.size();
        for (Index i = 0; i < n_; ++i) {
            node_[at(i)].pointer = static_cast<Index>(graph.offsets[at(i)]);
            node_[at(i)].length = static_cast<Index>(graph.degree(static_cast<std::uint32_t>(i)));
            node_[at(i)].degree = node_[at(i)].length;
        }
        for (std::size_t p = 0; p < edges; ++p) memory_[p] = graph.neighbors[p];
        used_ = static_cast<Index>(edges);
        dense_ = std::min(
            n_ - 2,
            std::max<Index>(16, static_cast<Index>(10.0 * std::sqrt(static_cast<double>(n_)))));
    }

    std::vector<std::uint32_t> run() {
        if (n_ == 0) return {};
        mark_ = clear_marks(0, 0);
        node_[at(n_)].elements = -2;
        node_[at(n_)].pointer = none;
        node_[at(n_)].stamp = 0;
        for (Index i = 0; i < n_; ++i) {
            const Index d = node_[at(i)].degree;
            if (d == 0) {
                node_[at(i)].elements = -2;  // an empty variable is an element at once
                ++eliminated_;
                node_[at(i)].pointer = none;
                node_[at(i)].stamp = 0;
            } else if (d > dense_) {
                node_[at(i)].size = 0;  // dense: absorbed into element n
                node_[at(i)].elements = -1;
                ++eliminated_;
                node_[at(i)].pointer = flip(n_);
                ++node_[at(n_)].size;
            } else {
                insert_degree_list(i, d);
            }
        }
        while (eliminated_ < n_) eliminate(select_pivot());
        return postorder();
    }

private:
    // Elbow room so that new elements rarely force a compaction.
    static std::size_t memory_size(std::size_t n, std::size_t edges) {
        return edges + edges / 5 + 2 * n + 1;
    }

    static std::size_t at(Index i) { return static_cast<std::size_t>(i); }

    void insert_degree_list(Index i, Index d) {
        if (head_[at(d)] != none) node_[at(head_[at(d)])].last = i;
        node_[at(i)].next = head_[at(d)];
        node_[at(i)].last = none;
        head_[at(d)] = i;
    }

    void remove_degree_list(Index i) {
        if (node_[at(i)].next != none) node_[at(node_[at(i)].next)].last = node_[at(i)].last;
        if (node_[at(i)].last != none) {
            node_[at(node_[at(i)].last)].next = node_[at(i)].next;
        } else {
            head_[at(node_[at(i)].degree)] = node_[at(i)].next;
        }
    }

    // node_[e].stamp ≥ mark_ means element e was seen in the current step (its
    // value then encodes |Le \ Lk|); 0 marks a dead element. Renumbers the
    // stamps when those of a step (up to `largest` above the mark) would
    // not fit in Index, and returns the mark to use next.
    Index clear_marks(Index mark, Index largest) {
        if (mark < 2 || mark > std::numeric_limits<Index>::max() - largest) {
            for (Index k = 0; k < n_; ++k)
                if (node_[at(k)].stamp != 0) node_[at(k)].stamp = 1;
            mark = 2;
        }
        return mark;
    }

    Index select_pivot() {
        Index k = none;
        while ((k = head_[at(min_degree_)]) == none) ++min_degree_;
        if (node_[at(k)].next != none) node_[at(node_[at(k)].next)].last = none;
        head_[at(min_degree_)] = node_[at(k)].next;
        return k;
    }

    // Packs every live list to the front of memory_.
    void compact() {
        for (Index j = 0; j < n_; ++j) {
            const Index p = node_[at(j)].pointer;
            if (p < 0) continue;
            node_[at(j)].pointer = memory_[at(p)];  // first entry kept aside
            memory_[at(p)] = flip(j);               // list start tagged with its owner
        }
        Index q = 0;
        for (Index p = 0; p < used_;) {
            const Index j = flip(memory_[at(p++)]);
            if (j < 0) continue;
            memory_[at(q)] = node_[at(j)].pointer;
            node_[at(j)].pointer = q++;
            for (Index t = 0; t < node_[at(j)].length - 1; ++t) memory_[at(q++)] = memory_[at(p++)];
        }
        used_ = q;
    }

    void eliminate(Index k) {
        const Index k_elements = node_[at(k)].elements;
        Index k_size = node_[at(k)].size;
        eliminated_ += k_size;
        if (k_elements > 0 && used_ + min_degree_ >= static_cast<Index>(memory_.size())) compact();

        // The new element's variables: k's own plus those of the elements
        // adjacent to k, which k absorbs. Members are flagged by a negated
        // size and leave the degree lists.
        Index degree_k = 0;
        node_[at(k)].size = -k_size;
        Index p = node_[at(k)].pointer;
        const Index lk_begin = k_elements == 0 ? p : used_;
        Index lk_end = lk_begin;
        for (Index source = 1; source <= k_elements + 1; ++source) {
            Index e;
            Index pj;
            Index count;
            if (source > k_elements) {
                e = k;
                pj = p;
                count = node_[at(k)].length - k_elements;
            } else {
                e = memory_[at(p++)];
                pj = node_[at(e)].pointer;
                count = node_[at(e)].length;
            }
            for (Index t = 0; t < count; ++t) {
                const Index i = memory_[at(pj++)];
                const Index size_i = node_[at(i)].size;
                if (size_i <= 0) continue;
                degree_k += size_i;
                node_[at(i)].size = -size_i;
                memory_[at(lk_end++)] = i;
                remove_degree_list(i);
            }
            if (e != k) {
                node_[at(e)].pointer = flip(k);
                node_[at(e)].stamp = 0;
            }
        }
        if (k_elements != 0) used_ = lk_end;
        node_[at(k)].degree = degree_k;
        node_[at(k)].pointer = lk_begin;
        node_[at(k)].length = lk_end - lk_begin;
        node_[at(k)].elements = -2;

        // |Le \ Lk| for every element e adjacent to a variable of Lk, as
        // node_[e].stamp − mark_.
        mark_ = clear_marks(mark_, largest_element_);
        for (Index pk = lk_begin; pk < lk_end; ++pk) {
            const Index i = memory_[at(pk)];
            const Index i_elements = node_[at(i)].elements;
            if (i_elements <= 0) continue;
            const Index size_i = -node_[at(i)].size;
            const Index first_visit = mark_ - size_i;
            for (Index q = node_[at(i)].pointer; q < node_[at(i)].pointer + i_elements; ++q) {
                const Index e = memory_[at(q)];
                if (node_[at(e)].stamp >= mark_) {
                    node_[at(e)].stamp -= size_i;
                } else if (node_[at(e)].stamp != 0) {
                    node_[at(e)].stamp = node_[at(e)].degree + first_visit;
                }
            }
        }

        // Approximate degrees; elements inside Lk are absorbed (aggressive
        // absorption), variables left with nothing outside are eliminated
        // with k (mass elimination), the rest hashed for supervariables.
        for (Index pk = lk_begin; pk < lk_end; ++pk) {
            const Index i = memory_[at(pk)];
            const Index p1 = node_[at(i)].pointer;
            const Index p2 = p1 + node_[at(i)].elements - 1;
            Index pn = p1;
            Index d = 0;
            std::uint64_t hash = 0;
            for (Index q = p1; q <= p2; ++q) {
                const Index e = memory_[at(q)];
                if (node_[at(e)].stamp == 0) continue;
                const Index outside = node_[at(e)].stamp - mark_;
                if (outside > 0) {
                    d += outside;
                    memory_[at(pn++)] = e;
                    hash += static_cast<std::uint64_t>(e);
                } else {
                    node_[at(e)].pointer = flip(k);
                    node_[at(e)].stamp = 0;
                }
            }
            node_[at(i)].elements = pn - p1 + 1;
            const Index p3 = pn;
            const Index p4 = p1 + node_[at(i)].length;
            for (Index q = p2 + 1; q < p4; ++q) {
                const Index j = memory_[at(q)];
                const Index size_j = node_[at(j)].size;
                if (size_j <= 0) continue;
                d += size_j;
                memory_[at(pn++)] = j;
                hash += static_cast<std::uint64_t>(j);
            }
            if (d == 0) {
                node_[at(i)].pointer = flip(k);
                const Index size_i = -node_[at(i)].size;
                degree_k -= size_i;
                k_size += size_i;
                eliminated_ += size_i;
                node_[at(i)].size = 0;
                node_[at(i)].elements = -1;
            } else {
                node_[at(i)].degree = std::min(node_[at(i)].degree, d);
                // k becomes i's first element.
                memory_[at(pn)] = memory_[at(p3)];
                memory_[at(p3)] = memory_[at(p1)];
                memory_[at(p1)] = k;
                node_[at(i)].length = pn - p1 + 1;
                const Index bucket = static_cast<Index>(hash % static_cast<std::uint64_t>(n_));
                node_[at(i)].next = hash_head_[at(bucket)];
                hash_head_[at(bucket)] = i;
                node_[at(i)].last = bucket;
            }
        }
        node_[at(k)].degree = degree_k;
        largest_element_ = std::max(largest_element_, degree_k);
        const bool room = mark_ <= std::numeric_limits<Index>::max() - 2 * largest_element_;
        mark_ = clear_marks(room ? mark_ + largest_element_ : 0, largest_element_);

        detect_supervariables(lk_begin, lk_end);

        // Back into the degree lists with their external degrees.
        Index write = lk_begin;
        for (Index pk = lk_begin; pk < lk_end; ++pk) {
            const Index i = memory_[at(pk)];
            const Index size_i = -node_[at(i)].size;
            if (size_i <= 0) continue;
            node_[at(i)].size = size_i;
            Index d = node_[at(i)].degree + degree_k - size_i;
            d = std::min(d, n_ - eliminated_ - size_i);
            node_[at(i)].degree = d;
            insert_degree_list(i, d);
            min_degree_ = std::min(min_degree_, d);
            memory_[at(write++)] = i;
        }
        node_[at(k)].size = k_size;
        node_[at(k)].length = write - lk_begin;
        if (node_[at(k)].length == 0) {
            node_[at(k)].pointer = none;
            node_[at(k)].stamp = 0;
        }
        if (k_elements != 0) used_ = write;
    }

    // Variables of Lk with identical lists (same hash first) are merged into
    // one supervariable.
    void detect_supervariables(Index lk_begin, Index lk_end) {
        for (Index pk = lk_begin; pk < lk_end; ++pk) {
            Index i = memory_[at(pk)];
            if (node_[at(i)].size >= 0) continue;
            const Index bucket = node_[at(i)].last;
            i = hash_head_[at(bucket)];
            hash_head_[at(bucket)] = none;
            for (; i != none && node_[at(i)].next != none; i = node_[at(i)].next, ++mark_) {
                const Index len = node_[at(i)].length;
                const Index elen = node_[at(i)].elements;
                for (Index q = node_[at(i)].pointer + 1; q <= node_[at(i)].pointer + len - 1; ++q)
                    node_[at(memory_[at(q)])].stamp = mark_;
                Index j_last = i;
                for (Index j = node_[at(i)].next; j != none;) {
                    bool same = node_[at(j)].length == len && node_[at(j)].elements == elen;
                    for (Index q = node_[at(j)].pointer + 1;
                         same && q <= node_[at(j)].pointer + len - 1; ++q)
                        same = node_[at(memory_[at(q)])].stamp == mark_;
                    if (same) {
                        node_[at(j)].pointer = flip(i);
                        node_[at(i)].size += node_[at(j)].size;
                        node_[at(j)].size = 0;
                        node_[at(j)].elements = -1;
                        j = node_[at(j)].next;
                        node_[at(j_last)].next = j;
                    } else {
                        j_last = j;
                        j = node_[at(j)].next;
                    }
                }
            }
        }
    }

    // Orders by a postorder of the assembly tree: absorbed variables just
    // before the element that absorbed them.
    std::vector<std::uint32_t> postorder() {
        for (Index i = 0; i < n_; ++i) node_[at(i)].pointer = flip(node_[at(i)].pointer);
        std::fill(head_.begin(), head_.end(), none);
        for (Index j = n_; j >= 0; --j) {
            if (node_[at(j)].size > 0) continue;
            node_[at(j)].next = head_[at(node_[at(j)].pointer)];
            head_[at(node_[at(j)].pointer)] = j;
        }
        for (Index e = n_; e >= 0; --e) {
            if (node_[at(e)].size <= 0 || node_[at(e)].pointer == none) continue;
            node_[at(e)].next = head_[at(node_[at(e)].pointer)];
            head_[at(node_[at(e)].pointer)] = e;
        }
        std::vector<std::uint32_t> order;
        order.reserve(at(n_) + 1);
        std::vector<Index> stack;
        for (Index root = 0; root <= n_; ++root) {
            if (node_[at(root)].pointer != none) continue;
            stack.push_back(root);
            while (!stack.empty()) {
                const Index p = stack.back();
                const Index child = head_[at(p)];
                if (child == none) {
                    stack.pop_back();
                    if (p < n_) order.push_back(static_cast<std::uint32_t>(p));
                } else {
                    head_[at(p)] = node_[at(child)].next;
                    stack.push_back(child);
                }
            }
        }
        return order;
    }

    Index n_;
    // A node's (a variable's or an element's) fields side by side: a step
    // reads and writes several of them for the same node, which then share
    // a cache line where eight arrays took one each.
    struct Node {
        Index pointer = 0;
        Index length = 0;
        Index size = 1;
        Index next = none;
        Index last = none;
        Index elements = 0;
        Index degree = 0;
        Index stamp = 1;
    };
    PooledVector<Node> node_;
    PooledVector<Index> head_;
    PooledVector<Index> hash_head_;
    PooledVector<Index> memory_;
    Index used_ = 0;
    Index dense_ = 0;
    Index mark_ = 0;
    Index min_degree_ = 0;
    Index largest_element_ = 0;
    Index eliminated_ = 0;
};

}  // namespace

std::vector<std::uint32_t> minimum_degree_ordering(const SymmetricGraph& graph) {
    if (MinimumDegree<std::int32_t>::fits(graph.size(), graph.neighbors.size()))
        return MinimumDegree<std::int32_t>(graph).run();
    return minimum_degree_ordering_64(graph);
}

std::vector<std::uint32_t> minimum_degree_ordering_64(const SymmetricGraph& graph) {
    return MinimumDegree<std::int64_t>(graph).run();
}

}  // namespace dfm::solver
