#include "deform/row_order.hpp"

#include <vector>

#include "mesh/mesh.hpp"

namespace dfm::deform {

void order_by_patch(RotationClusters& clusters, SystemRows& rows, UnknownMap& unknowns,
                    std::span<std::uint32_t> soft_handles) {
    const std::size_t count = rows.size();
    // A counting sort by patch; a row no patch holds (none, unless the
    // clusters are empty) goes last.
    const std::size_t patches = clusters.patch_count();
    const auto bucket = [&](std::size_t r) {
        const std::uint32_t p = clusters.patch_of(r);
        return p < patches ? p : patches;
    };
    std::vector<std::uint32_t> start(patches + 2, 0);
    for (std::size_t r = 0; r < count; ++r) ++start[bucket(r) + 1];
    for (std::size_t p = 0; p <= patches; ++p) start[p + 1] += start[p];
    std::vector<std::uint32_t> old_row_of(count);
    for (std::size_t r = 0; r < count; ++r)
        old_row_of[start[bucket(r)]++] = static_cast<std::uint32_t>(r);

    // The rows gathered in their new order, each unknown numbered as the
    // first of them names it. The rows lie apart: a row's place is fetched
    // 2 · ahead rows before it is copied, and its entries ahead rows before.
    constexpr std::size_t ahead = 8;
    std::vector<std::uint32_t> new_unknown(unknowns.count(), mesh::no_index);
    std::uint32_t numbered = 0;
    SystemRows ordered;
    ordered.faces.reserve(count);
    ordered.entry_offsets.reserve(count + 1);
    ordered.entries.reserve(rows.entries.size());
    ordered.entry_offsets.push_back(0);
    for (std::size_t k = 0; k < count; ++k) {
        if (k + 2 * ahead < count) {
            __builtin_prefetch(&rows.entry_offsets[old_row_of[k + 2 * ahead]]);
            __builtin_prefetch(&rows.faces[old_row_of[k + 2 * ahead]]);
        }
        if (k + ahead < count)
            __builtin_prefetch(&rows.entries[rows.entry_offsets[old_row_of[k + ahead]]]);
        const std::uint32_t r = old_row_of[k];
        ordered.faces.push_back(rows.faces[r]);
        for (std::uint32_t e = rows.entry_offsets[r]; e < rows.entry_offsets[r + 1]; ++e) {
            RowEntry entry = rows.entries[e];
            if (entry.unknown != mesh::no_index) {
                std::uint32_t& u = new_unknown[entry.unknown];
                if (u == mesh::no_index) u = numbered++;
                entry.unknown = u;
            }
            ordered.entries.push_back(entry);
        }
        ordered.entry_offsets.push_back(static_cast<std::uint32_t>(ordered.entries.size()));
    }
    for (std::uint32_t& u : new_unknown) {
        if (u == mesh::no_index) u = numbered++;
    }
    ordered.centroid_faces = std::move(rows.centroid_faces);
    rows = std::move(ordered);

    std::vector<std::uint32_t> vertex_of_unknown(unknowns.count());
    for (std::size_t u = 0; u < unknowns.count(); ++u) {
        const std::uint32_t v = unknowns.vertex_of_unknown[u];
        vertex_of_unknown[new_unknown[u]] = v;
        unknowns.unknown_of_vertex[v] = new_unknown[u];
    }
    unknowns.vertex_of_unknown = std::move(vertex_of_unknown);
    for (std::uint32_t& u : soft_handles) u = new_unknown[u];
    clusters.reorder_rows(old_row_of);
}

}  // namespace dfm::deform
