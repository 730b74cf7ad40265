#include "roi/set_ops.hpp"

#include <algorithm>
#include <iterator>

#include "roi/vertex_list.hpp"

namespace dfm::roi {

Status roi_union(std::span<const std::uint32_t> a, std::span<const std::uint32_t> b,
                 std::size_t vertex_count, std::vector<std::uint32_t>& out) {
    out.clear();
    if (Status s = check_roi(a, vertex_count, "union.a"); !s) return s;
    if (Status s = check_roi(b, vertex_count, "union.b"); !s) return s;
    std::set_union(a.begin(), a.end(), b.begin(), b.end(), std::back_inserter(out));
    return Status::ok();
}

Status roi_difference(std::span<const std::uint32_t> a, std::span<const std::uint32_t> b,
                      std::size_t vertex_count, std::vector<std::uint32_t>& out) {
    out.clear();
    if (Status s = check_roi(a, vertex_count, "difference.a"); !s) return s;
    if (Status s = check_roi(b, vertex_count, "difference.b"); !s) return s;
    std::set_difference(a.begin(), a.end(), b.begin(), b.end(), std::back_inserter(out));
    return Status::ok();
}

}  // namespace dfm::roi
