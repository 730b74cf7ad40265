#include <map>
#include <set>

#include <nlohmann/json.hpp>

#include "mesh/gltf_edit.hpp"

namespace dfm::mesh {

namespace {

using nlohmann::json;

std::size_t accessor_count(const json& doc, const json& primitive) {
    const auto attributes = primitive.find("attributes");
    if (attributes == primitive.end() || !attributes->contains("POSITION")) return 0;
    const json& index = (*attributes)["POSITION"];
    if (!doc.contains("accessors") || !index.is_number_unsigned() ||
        index.get<std::size_t>() >= doc["accessors"].size()) {
        return 0;
    }
    const json& accessor = doc["accessors"][index.get<std::size_t>()];
    return accessor.is_object() ? accessor.value("count", std::size_t{0}) : 0;
}

void extend_weights(json& owner) {
    if (owner.is_object() && owner.contains("weights") && owner["weights"].is_array()) {
        owner["weights"].push_back(0.0);
    }
}

// Every sampler that animates the weights of a node instancing one of
// `meshes` gets a new output: each key's `width` values and a 0.
void widen_weight_samplers(const GltfAsset& asset, const std::set<int>& meshes, json& doc,
                           const AppendAccessor& append) {
    std::set<std::pair<int, int>> done;
    for (const GltfWeightSampler& w : asset.weight_samplers) {
        if (!done.insert({w.animation, w.sampler}).second) continue;
        const json& node = doc["nodes"][w.node];
        if (!node.is_object() || meshes.count(node.value("mesh", -1)) == 0) continue;
        std::vector<float> widened;
        widened.reserve(w.values.size() / w.width * (w.width + 1));
        for (std::size_t i = 0; i < w.values.size(); ++i) {
            widened.push_back(static_cast<float>(w.values[i]));
            if ((i + 1) % w.width == 0) widened.push_back(0.0f);
        }
        doc["animations"][w.animation]["samplers"][w.sampler]["output"] = append(widened, 1, false);
    }
}

}  // namespace

void add_morph_target(const GltfAsset& asset, const EditedVertices& edit, const std::string& name,
                      const std::string& extras, json& doc, const AppendAccessor& append) {
    std::set<int> touched;
    for (const GltfVertexRange& r : asset.ranges) {
        for (std::uint32_t v = r.first_vertex; v < r.first_vertex + r.count; ++v) {
            if (edit.dirty[v]) {
                touched.insert(r.mesh);
                break;
            }
        }
    }
    std::map<std::pair<int, int>, const GltfPrimitive*> loaded;
    for (const GltfPrimitive& p : asset.primitives) loaded[{p.mesh, p.primitive}] = &p;
    // One pair of delta accessors per range, shared by the primitives that
    // share its POSITION.
    std::map<std::uint32_t, std::pair<int, int>> deltas_of_range;
    const auto deltas = [&](std::uint32_t index) {
        if (const auto it = deltas_of_range.find(index); it != deltas_of_range.end()) {
            return it->second;
        }
        const GltfVertexRange& r = asset.ranges[index];
        std::vector<float> dp(3 * r.count), dn(3 * r.count);
        for (std::uint32_t i = 0; i < r.count; ++i) {
            const std::size_t v = r.first_vertex + i;
            for (int c = 0; c < 3; ++c) {
                // The delta is taken between the float values a reader sees,
                // so base + delta lands on the edited position.
                dp[3 * i + c] = static_cast<float>(edit.local_positions[v][c]) -
                                static_cast<float>(asset.local_positions[v][c]);
                dn[3 * i + c] = static_cast<float>(edit.normals[v][c]) -
                                static_cast<float>(asset.normals[v][c]);
            }
        }
        const int p = append(dp, 3, true);
        if (!extras.empty()) {
            json record = json::parse(extras, nullptr, false);
            if (record.is_object()) doc["accessors"][p]["extras"] = std::move(record);
        }
        const int nrm = r.normal.accessor >= 0 ? append(dn, 3, false) : -1;
        return deltas_of_range[index] = {p, nrm};
    };
    for (int m : touched) {
        json& mesh = doc["meshes"][m];
        json& primitives = mesh["primitives"];
        std::size_t existing = 0;
        for (std::size_t p = 0; p < primitives.size(); ++p) {
            json& prim = primitives[p];
            if (prim.contains("targets") && prim["targets"].is_array()) {
                existing = prim["targets"].size();
            }
            json target = json::object();
            const auto it = loaded.find({m, static_cast<int>(p)});
            if (it != loaded.end()) {
                const auto [position, normal] = deltas(it->second->range);
                target["POSITION"] = position;
                if (normal >= 0 && prim["attributes"].contains("NORMAL")) target["NORMAL"] = normal;
            } else {
                const std::size_t count = accessor_count(doc, prim);
                target["POSITION"] = append(std::vector<float>(3 * count, 0.0f), 3, true);
            }
            prim["targets"].push_back(target);
        }
        extend_weights(mesh);
        if (!mesh.contains("extras")) mesh["extras"] = json::object();
        json& extras = mesh["extras"];
        if (extras.is_object()) {
            json& names = extras["targetNames"];
            if (!names.is_array()) names = json::array();
            while (names.size() < existing)
                names.push_back("target_" + std::to_string(names.size()));
            names.push_back(name);
        }
        if (!doc.contains("nodes")) continue;
        for (json& node : doc["nodes"]) {
            if (node.is_object() && node.value("mesh", -1) == m) extend_weights(node);
        }
    }
    widen_weight_samplers(asset, touched, doc, append);
}

}  // namespace dfm::mesh
