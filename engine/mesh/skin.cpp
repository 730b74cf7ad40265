#include "mesh/skin.hpp"

#include <algorithm>

namespace dfm::mesh {

std::size_t Skin::skinned_vertex_count() const {
    std::size_t n = 0;
    for (std::size_t v = 0; v < vertex_count(); ++v) {
        if (influence_offsets[v + 1] > influence_offsets[v]) ++n;
    }
    return n;
}

void add_influence(InfluenceList& list, std::uint32_t joint, double weight) {
    const auto same =
        std::find_if(list.begin(), list.end(), [&](const auto& e) { return e.first == joint; });
    if (same != list.end()) {
        same->second += weight;
    } else {
        list.push_back({joint, weight});
    }
}

void set_influences(std::vector<InfluenceList>& lists, Skin& skin) {
    skin.influence_offsets.assign(lists.size() + 1, 0);
    skin.influence_joints.clear();
    skin.influence_weights.clear();
    skin.max_influences = 0;
    for (std::size_t v = 0; v < lists.size(); ++v) {
        InfluenceList& list = lists[v];
        std::sort(list.begin(), list.end());
        double sum = 0.0;
        for (const auto& e : list) sum += e.second;
        for (const auto& [joint, weight] : list) {
            skin.influence_joints.push_back(joint);
            skin.influence_weights.push_back(weight / sum);
        }
        skin.max_influences =
            std::max(skin.max_influences, static_cast<std::uint32_t>(list.size()));
        skin.influence_offsets[v + 1] = static_cast<std::uint32_t>(skin.influence_joints.size());
    }
}

}  // namespace dfm::mesh
