#include "roi/vertex_list.hpp"

#include <algorithm>
#include <string>

namespace dfm::roi {

namespace {

Status out_of_range(std::string_view what, std::size_t i, std::uint32_t v, std::size_t n) {
    std::string message(what);
    message += '[';
    message += std::to_string(i);
    message += "]: vertex ";
    message += std::to_string(v);
    message += " is out of range (the mesh has ";
    message += std::to_string(n);
    message += " vertices)";
    return Status(Errc::out_of_range, std::move(message));
}

}  // namespace

Status select_vertices(std::span<const std::uint32_t> list, std::size_t vertex_count,
                       std::vector<std::uint32_t>& out) {
    out.clear();
    for (std::size_t i = 0; i < list.size(); ++i) {
        if (list[i] >= vertex_count) return out_of_range("vertices", i, list[i], vertex_count);
    }
    out.assign(list.begin(), list.end());
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
    return Status::ok();
}

Status check_roi(std::span<const std::uint32_t> roi, std::size_t vertex_count,
                 std::string_view what) {
    for (std::size_t i = 0; i < roi.size(); ++i) {
        if (roi[i] >= vertex_count) return out_of_range(what, i, roi[i], vertex_count);
        if (i > 0 && roi[i] <= roi[i - 1]) {
            std::string message(what);
            message += '[';
            message += std::to_string(i);
            message += "]: the ROI must be strictly ascending, but ";
            message += std::to_string(roi[i]);
            message += " follows ";
            message += std::to_string(roi[i - 1]);
            return Status(Errc::invalid_argument, std::move(message));
        }
    }
    return Status::ok();
}

}  // namespace dfm::roi
