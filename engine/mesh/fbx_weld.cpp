#include <map>
#include <tuple>

#include "mesh/fbx_io.hpp"
#include "mesh/skin_weld.hpp"

namespace dfm::mesh {

namespace {

// One class per distinct (skin class, morph deltas) of a host vertex.
std::vector<std::uint32_t> skin_and_morph_classes(const Skin& skin) {
    std::vector<std::uint32_t> cls = skin_classes(skin);
    if (skin.morph_targets.empty()) return cls;
    const std::size_t n = skin.vertex_count();
    std::vector<std::vector<double>> signature(n);
    for (std::size_t t = 0; t < skin.morph_targets.size(); ++t) {
        const MorphTarget& target = skin.morph_targets[t];
        for (std::size_t i = 0; i < target.vertices.size(); ++i) {
            std::vector<double>& s = signature[target.vertices[i]];
            s.insert(s.end(), {static_cast<double>(t), target.deltas[i].x, target.deltas[i].y,
                               target.deltas[i].z});
        }
    }
    std::map<std::pair<std::uint32_t, std::vector<double>>, std::uint32_t> ids;
    for (std::size_t v = 0; v < n; ++v) {
        cls[v] = ids.try_emplace({cls[v], std::move(signature[v])},
                                 static_cast<std::uint32_t>(ids.size()))
                     .first->second;
    }
    return cls;
}

}  // namespace

void weld_fbx(const Mesh& host, const Skin& host_skin, const WeldOptions& options,
              const std::string& source, Mesh& surface, SeamWeld& weld,
              std::shared_ptr<const Skin>& surface_skin, LoadReport& report) {
    const std::vector<std::uint32_t> classes = skin_and_morph_classes(host_skin);
    weld_seams(host.positions, host.triangles, options, surface, weld, classes);
    surface_skin.reset();
    if (host_skin.vertex_count() == 0) return;
    surface_skin = std::make_shared<const Skin>(skin_on_surface(host_skin, weld));
    if (weld.kept_apart > 0) {
        const std::string what = std::to_string(weld.kept_apart) +
                                 " positions have control points that faces connect but whose "
                                 "skins or morph deltas differ; they were not welded, and the "
                                 "surface has a seam there";
        report.warn(source + ": " + what);
    }
}

}  // namespace dfm::mesh
