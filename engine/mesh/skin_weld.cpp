#include "mesh/skin_weld.hpp"

#include <algorithm>
#include <map>
#include <tuple>

namespace dfm::mesh {

std::vector<std::uint32_t> skin_classes(const Skin& skin, WeldBy by) {
    const std::size_t n = skin.vertex_count();
    if (n == 0) return {};
    // A vertex's signature: its joints and weights, then for every target
    // that moves it (when morphs count) the target and its delta.
    std::vector<std::vector<double>> signature(n);
    for (std::size_t v = 0; v < n; ++v) {
        for (std::uint32_t k = skin.influence_offsets[v]; k < skin.influence_offsets[v + 1]; ++k) {
            signature[v].push_back(skin.influence_joints[k]);
            signature[v].push_back(skin.influence_weights[k]);
        }
        signature[v].push_back(-1.0);
    }
    if (by == WeldBy::skin_and_morphs) {
        for (std::size_t t = 0; t < skin.morph_targets.size(); ++t) {
            const MorphTarget& target = skin.morph_targets[t];
            for (std::size_t i = 0; i < target.vertices.size(); ++i) {
                std::vector<double>& s = signature[target.vertices[i]];
                s.insert(s.end(), {static_cast<double>(t), target.deltas[i].x, target.deltas[i].y,
                                   target.deltas[i].z});
            }
        }
    }
    std::map<std::vector<double>, std::uint32_t> ids;
    std::vector<std::uint32_t> cls(n);
    for (std::size_t v = 0; v < n; ++v) {
        cls[v] = ids.try_emplace(std::move(signature[v]), static_cast<std::uint32_t>(ids.size()))
                     .first->second;
    }
    return cls;
}

namespace {

// Surface vertices with a copy whose delta in some target is not the
// lowest copy's.
std::size_t morph_disagreements(const Skin& skin, const SeamWeld& weld) {
    if (skin.morph_targets.empty() || !weld.splits()) return 0;
    std::vector<bool> differs(weld.surface_vertex_count(), false);
    std::vector<glm::dvec3> delta(weld.host_vertex_count(), glm::dvec3(0.0));
    for (const MorphTarget& target : skin.morph_targets) {
        for (std::size_t i = 0; i < target.vertices.size(); ++i) {
            delta[target.vertices[i]] = target.deltas[i];
        }
        for (std::uint32_t h = 0; h < weld.host_vertex_count(); ++h) {
            const std::uint32_t s = weld.surface_of[h];
            if (delta[h] != delta[weld.lowest_copy(s)]) differs[s] = true;
        }
        for (std::uint32_t v : target.vertices) delta[v] = glm::dvec3(0.0);
    }
    return static_cast<std::size_t>(std::count(differs.begin(), differs.end(), true));
}

}  // namespace

Skin skin_on_surface(const Skin& host_skin, const SeamWeld& weld) {
    Skin out;
    out.joint_names = host_skin.joint_names;
    out.joint_nodes = host_skin.joint_nodes;
    out.inverse_bind = host_skin.inverse_bind;
    out.nodes = host_skin.nodes;
    out.animations = host_skin.animations;
    out.max_influences = host_skin.max_influences;
    const std::size_t surfaces = weld.surface_vertex_count();
    out.influence_offsets.assign(surfaces + 1, 0);
    for (std::uint32_t s = 0; s < surfaces; ++s) {
        const std::uint32_t h = weld.lowest_copy(s);
        for (std::uint32_t k = host_skin.influence_offsets[h];
             k < host_skin.influence_offsets[h + 1]; ++k) {
            out.influence_joints.push_back(host_skin.influence_joints[k]);
            out.influence_weights.push_back(host_skin.influence_weights[k]);
        }
        out.influence_offsets[s + 1] = static_cast<std::uint32_t>(out.influence_joints.size());
    }
    for (const MorphTarget& target : host_skin.morph_targets) {
        MorphTarget t = target;
        t.vertices.clear();
        t.deltas.clear();
        for (std::size_t i = 0; i < target.vertices.size(); ++i) {
            const std::uint32_t h = target.vertices[i];
            const std::uint32_t s = weld.surface_of[h];
            if (weld.lowest_copy(s) != h) continue;
            t.vertices.push_back(s);
            t.deltas.push_back(target.deltas[i]);
        }
        // Surface vertices follow their lowest copies' order, so the list
        // stays ascending.
        out.morph_targets.push_back(std::move(t));
    }
    return out;
}

void weld_skinned(const Mesh& split, const Skin& host_skin, WeldBy by, const WeldOptions& options,
                  const std::string& source, Mesh& surface, SeamWeld& weld,
                  std::shared_ptr<const Skin>& surface_skin, LoadReport& report) {
    const std::vector<std::uint32_t> classes = skin_classes(host_skin, by);
    weld_seams(split.positions, split.triangles, options, surface, weld, classes);
    surface_skin.reset();
    if (host_skin.vertex_count() == 0) return;
    surface_skin = std::make_shared<const Skin>(skin_on_surface(host_skin, weld));
    const auto warn = [&](const std::string& what) { report.warn(source + ": " + what); };
    if (weld.kept_apart > 0) {
        warn(std::to_string(weld.kept_apart) + " positions have copies that faces connect but " +
             (by == WeldBy::skin ? "whose skins (joints or weights) differ"
                                 : "whose skins or morph deltas differ") +
             "; they were not welded, and the surface has a seam there");
    }
    const std::size_t differing = morph_disagreements(host_skin, weld);
    if (differing > 0) {
        warn(std::to_string(differing) +
             " surface vertices have copies whose morph target deltas differ; posed, each "
             "takes its lowest copy's");
    }
}

}  // namespace dfm::mesh
