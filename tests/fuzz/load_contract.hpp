#pragma once

#include <cmath>
#include <cstdint>
#include <string_view>

#include "core/status.hpp"
#include "mesh/load.hpp"

// What parse_mesh promises for any bytes, checked by the fuzz targets and by
// the unit test that replays their findings (tests/data/fuzz-regressions/).
namespace dfm::test {

inline bool load_contract_holds(const Status& status, const mesh::Mesh& mesh,
                                const mesh::LoadReport& report, std::string_view source) {
    if (!status) {
        // A failed load leaves nothing behind and says where it failed.
        return mesh.positions.empty() && mesh.triangles.empty() &&
               std::string_view(status.message()).starts_with(source);
    }
    if (report.warnings.size() > mesh::LoadReport::max_warnings) return false;
    for (const mesh::Triangle& t : mesh.triangles) {
        for (std::uint32_t v : t) {
            if (v >= mesh.vertex_count()) return false;
        }
        if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) return false;
    }
    for (const auto& p : mesh.positions) {
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) return false;
    }
    return true;
}

}  // namespace dfm::test
