#include "mesh/gltf_skin_reader.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <utility>

#include <glm/gtc/type_ptr.hpp>
#include <glm/matrix.hpp>

#include "mesh/gltf_accessors.hpp"

namespace dfm::mesh {

namespace {

// glTF's JOINTS_n are unsigned bytes or shorts: a skin cannot address more.
constexpr std::size_t max_skin_joints = 65536;

class SkinReader {
public:
    SkinReader(const tinygltf::Model& model, std::string_view source, GltfAsset& asset, Skin& skin,
               LoadReport& report)
        : model_(model), source_(source), asset_(asset), skin_(skin), report_(report) {}

    Status nodes();
    Status joints();
    Status influences();
    Status morph_targets();
    Status animations();

private:
    Status error(Errc code, const std::string& what) const {
        return Status(code, std::string(source_) + ": " + what);
    }
    Status located(const Status& s) const { return error(s.code(), s.message()); }
    void warn(const std::string& what) { report_.warn(std::string(source_) + ": " + what); }
    const tinygltf::Primitive& first_primitive(std::uint32_t range) const;
    Status vertex_influences(const GltfVertexRange& r, const tinygltf::Primitive& prim,
                             std::uint32_t joint_base, std::size_t joint_count,
                             std::vector<InfluenceList>& out);
    Status channel(std::size_t a, std::size_t c, Animation& out, bool& keep);

    const tinygltf::Model& model_;
    std::string_view source_;
    GltfAsset& asset_;
    Skin& skin_;
    LoadReport& report_;
    std::map<int, std::uint32_t> joint_base_;  // skin -> its first joint in skin_'s list
};

Status SkinReader::nodes() {
    const std::size_t n = model_.nodes.size();
    skin_.nodes.assign(n, SkeletonNode{});
    for (std::size_t i = 0; i < n; ++i) {
        const tinygltf::Node& node = model_.nodes[i];
        SkeletonNode& out = skin_.nodes[i];
        out.name = node.name.empty() ? "node_" + std::to_string(i) : node.name;
        for (int child : node.children) {
            if (child < 0 || static_cast<std::size_t>(child) >= n) {
                return error(Errc::out_of_range,
                             "node " + std::to_string(i) + ": child " + std::to_string(child) +
                                 " does not exist (the file has " + std::to_string(n) + " nodes)");
            }
            if (skin_.nodes[child].parent != no_index || static_cast<std::size_t>(child) == i) {
                return error(Errc::parse_error, "node " + std::to_string(child) +
                                                    " has two parents: the node hierarchy must "
                                                    "be a forest");
            }
            skin_.nodes[child].parent = static_cast<std::uint32_t>(i);
        }
        if (node.matrix.size() == 16) {
            out.has_matrix = true;
            out.matrix = glm::make_mat4(node.matrix.data());
        }
        if (node.translation.size() == 3) {
            out.translation =
                glm::dvec3(node.translation[0], node.translation[1], node.translation[2]);
        }
        if (node.rotation.size() == 4) {
            out.rotation = glm::normalize(
                glm::dquat(node.rotation[3], node.rotation[0], node.rotation[1], node.rotation[2]));
        }
        if (node.scale.size() == 3) {
            out.scale = glm::dvec3(node.scale[0], node.scale[1], node.scale[2]);
        }
    }
    // A cycle has every member with a parent: walking up from each node
    // must reach a root within n steps.
    for (std::size_t i = 0; i < n; ++i) {
        std::size_t steps = 0;
        for (std::uint32_t at = static_cast<std::uint32_t>(i); at != no_index;
             at = skin_.nodes[at].parent) {
            if (++steps > n) {
                return error(Errc::parse_error, "node " + std::to_string(i) +
                                                    " is its own ancestor: the node "
                                                    "hierarchy must be a forest");
            }
        }
    }
    return Status::ok();
}

Status SkinReader::joints() {
    std::set<int> used;
    for (const GltfVertexRange& r : asset_.ranges) {
        if (r.skin < 0) continue;
        if (static_cast<std::size_t>(r.skin) >= model_.skins.size()) {
            return error(Errc::out_of_range, "node " + std::to_string(r.node) + ": skin " +
                                                 std::to_string(r.skin) +
                                                 " does not exist (the file has " +
                                                 std::to_string(model_.skins.size()) + ")");
        }
        used.insert(r.skin);
    }
    for (int s : used) {
        const tinygltf::Skin& skin = model_.skins[s];
        const std::string where = "skin " + std::to_string(s);
        if (skin.joints.empty()) return error(Errc::parse_error, where + " has no joints");
        if (skin.joints.size() > max_skin_joints) {
            return error(Errc::unsupported,
                         where + " has " + std::to_string(skin.joints.size()) +
                             " joints, more than glTF's JOINTS attributes address (65,536)");
        }
        std::vector<double> matrices;
        if (skin.inverseBindMatrices >= 0) {
            const std::string what = where + " inverseBindMatrices";
            if (Status s = check_accessor_shape(model_, skin.inverseBindMatrices,
                                                TINYGLTF_TYPE_MAT4, what);
                !s) {
                return located(s);
            }
            if (Status s = read_accessor(model_, skin.inverseBindMatrices, 16, what, matrices);
                !s) {
                return located(s);
            }
            if (matrices.size() / 16 < skin.joints.size()) {
                return error(Errc::parse_error,
                             what + " (accessor " + std::to_string(skin.inverseBindMatrices) +
                                 ") has " + std::to_string(matrices.size() / 16) +
                                 " matrices for " + std::to_string(skin.joints.size()) + " joints");
            }
        }
        joint_base_[s] = static_cast<std::uint32_t>(skin_.joint_count());
        for (std::size_t j = 0; j < skin.joints.size(); ++j) {
            const int node = skin.joints[j];
            if (node < 0 || static_cast<std::size_t>(node) >= model_.nodes.size()) {
                return error(Errc::out_of_range, where + " joint " + std::to_string(j) + ": node " +
                                                     std::to_string(node) +
                                                     " does not exist (the file has " +
                                                     std::to_string(model_.nodes.size()) + ")");
            }
            glm::dmat4 ibm(1.0);
            if (!matrices.empty()) ibm = glm::make_mat4(matrices.data() + 16 * j);
            const double det = glm::determinant(ibm);
            if (!std::isfinite(det) || std::abs(det) < 1e-30) {
                return error(Errc::numerical,
                             where + " joint " + std::to_string(j) + " (node " +
                                 std::to_string(node) + "): its inverse bind matrix is " +
                                 (std::isfinite(det) ? "not invertible" : "not finite"));
            }
            skin_.joint_nodes.push_back(static_cast<std::uint32_t>(node));
            skin_.joint_names.push_back(skin_.nodes[node].name);
            skin_.inverse_bind.push_back(ibm);
        }
    }
    return Status::ok();
}

const tinygltf::Primitive& SkinReader::first_primitive(std::uint32_t range) const {
    for (const GltfPrimitive& p : asset_.primitives) {
        if (p.range == range) return model_.meshes[p.mesh].primitives[p.primitive];
    }
    // Every range comes from a primitive (gltf_reader.cpp adds both together).
    return model_.meshes[asset_.ranges[range].mesh].primitives.front();
}

Status SkinReader::vertex_influences(const GltfVertexRange& r, const tinygltf::Primitive& prim,
                                     std::uint32_t joint_base, std::size_t joint_count,
                                     std::vector<InfluenceList>& out) {
    const std::string where = "mesh " + std::to_string(r.mesh);
    for (int set = 0;; ++set) {
        const std::string joints_name = "JOINTS_" + std::to_string(set);
        const std::string weights_name = "WEIGHTS_" + std::to_string(set);
        const auto joints = prim.attributes.find(joints_name);
        const auto weights = prim.attributes.find(weights_name);
        if (joints == prim.attributes.end() && weights == prim.attributes.end()) {
            if (set == 0) {
                return error(Errc::parse_error, where + " is skinned (node " +
                                                    std::to_string(r.node) +
                                                    ") but has no JOINTS_0 and WEIGHTS_0");
            }
            return Status::ok();
        }
        if (joints == prim.attributes.end() || weights == prim.attributes.end()) {
            return error(Errc::parse_error, where + " has " +
                                                (joints == prim.attributes.end()
                                                     ? weights_name + " without " + joints_name
                                                     : joints_name + " without " + weights_name));
        }
        const std::string jwhat = where + " " + joints_name;
        const std::string wwhat = where + " " + weights_name;
        if (Status s = check_accessor_shape(model_, joints->second, TINYGLTF_TYPE_VEC4, jwhat);
            !s) {
            return located(s);
        }
        if (Status s = check_accessor_shape(model_, weights->second, TINYGLTF_TYPE_VEC4, wwhat);
            !s) {
            return located(s);
        }
        const int jtype = model_.accessors[joints->second].componentType;
        if (jtype != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE &&
            jtype != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT) {
            return error(Errc::parse_error, jwhat + " (accessor " + std::to_string(joints->second) +
                                                "): component type " + std::to_string(jtype) +
                                                " is not an unsigned byte or short");
        }
        std::vector<double> j, w;
        if (Status s = read_accessor(model_, joints->second, 4, jwhat, j); !s) return located(s);
        if (Status s = read_accessor(model_, weights->second, 4, wwhat, w); !s) return located(s);
        if (j.size() / 4 != r.count || w.size() / 4 != r.count) {
            return error(Errc::parse_error, where + ": " + joints_name + " has " +
                                                std::to_string(j.size() / 4) + " and " +
                                                weights_name + " " + std::to_string(w.size() / 4) +
                                                " elements, POSITION " + std::to_string(r.count));
        }
        for (std::uint32_t v = 0; v < r.count; ++v) {
            for (int k = 0; k < 4; ++k) {
                const double weight = w[4 * v + k];
                const double joint = j[4 * v + k];
                const std::string at =
                    " element " + std::to_string(v) + " component " + std::to_string(k);
                if (!std::isfinite(weight) || weight < 0.0) {
                    return error(Errc::numerical, wwhat + at + ": weight " +
                                                      std::to_string(weight) +
                                                      " is negative or not finite");
                }
                if (joint >= static_cast<double>(joint_count)) {
                    return error(Errc::out_of_range,
                                 jwhat + at + ": joint " +
                                     std::to_string(static_cast<std::uint64_t>(joint)) +
                                     " is beyond the skin's " + std::to_string(joint_count) +
                                     " joints");
                }
                if (weight == 0.0) continue;
                add_influence(out[r.first_vertex + v],
                              joint_base + static_cast<std::uint32_t>(joint), weight);
            }
        }
    }
}

Status SkinReader::influences() {
    const std::size_t n = asset_.local_positions.size();
    std::vector<InfluenceList> lists(n);
    for (std::uint32_t ri = 0; ri < asset_.ranges.size(); ++ri) {
        const GltfVertexRange& r = asset_.ranges[ri];
        if (r.skin < 0) continue;
        const std::size_t count = model_.skins[r.skin].joints.size();
        if (Status s =
                vertex_influences(r, first_primitive(ri), joint_base_.at(r.skin), count, lists);
            !s) {
            return s;
        }
        for (std::uint32_t v = r.first_vertex; v < r.first_vertex + r.count; ++v) {
            if (lists[v].empty()) {
                return error(Errc::numerical, "mesh " + std::to_string(r.mesh) + " vertex " +
                                                  std::to_string(v - r.first_vertex) +
                                                  ": its skin weights sum to 0");
            }
        }
    }
    set_influences(lists, skin_);
    return Status::ok();
}

std::string target_name(const tinygltf::Mesh& mesh, std::size_t k) {
    const tinygltf::Value& names = mesh.extras.Get("targetNames");
    if (names.IsArray() && k < names.ArrayLen() && names.Get(static_cast<int>(k)).IsString()) {
        return names.Get(static_cast<int>(k)).Get<std::string>();
    }
    return "target_" + std::to_string(k);
}

Status SkinReader::morph_targets() {
    // One target per (mesh, k), over every range of the mesh.
    std::map<int, std::size_t> first_target;  // mesh -> index of its target 0
    for (std::uint32_t ri = 0; ri < asset_.ranges.size(); ++ri) {
        const GltfVertexRange& r = asset_.ranges[ri];
        const tinygltf::Primitive& prim = first_primitive(ri);
        if (prim.targets.empty()) continue;
        const tinygltf::Mesh& mesh = model_.meshes[r.mesh];
        const std::string where = "mesh " + std::to_string(r.mesh);
        auto [it, added] = first_target.try_emplace(r.mesh, skin_.morph_targets.size());
        if (added) {
            const tinygltf::Node* node = r.node >= 0 ? &model_.nodes[r.node] : nullptr;
            for (std::size_t k = 0; k < prim.targets.size(); ++k) {
                MorphTarget t;
                t.name = target_name(mesh, k);
                t.node = r.node >= 0 ? static_cast<std::uint32_t>(r.node) : no_index;
                t.column = static_cast<std::uint32_t>(k);
                if (node != nullptr && node->weights.size() == prim.targets.size()) {
                    t.default_weight = node->weights[k];
                } else if (mesh.weights.size() == prim.targets.size()) {
                    t.default_weight = mesh.weights[k];
                }
                if (!std::isfinite(t.default_weight)) {
                    return error(Errc::numerical, where + " morph target " + std::to_string(k) +
                                                      ": its default weight is not finite");
                }
                skin_.morph_targets.push_back(std::move(t));
            }
        } else if (skin_.morph_targets.size() - it->second < prim.targets.size()) {
            return error(Errc::parse_error,
                         where + ": its primitives have different numbers of morph targets");
        }
        const glm::dmat3 linear(r.world);
        for (std::size_t k = 0; k < prim.targets.size(); ++k) {
            const auto position = prim.targets[k].find("POSITION");
            if (position == prim.targets[k].end()) continue;
            const std::string what = where + " morph target " + std::to_string(k) + " POSITION";
            if (Status s = check_accessor_shape(model_, position->second, TINYGLTF_TYPE_VEC3, what);
                !s) {
                return located(s);
            }
            std::vector<double> d;
            if (Status s = read_accessor(model_, position->second, 3, what, d); !s) {
                return located(s);
            }
            if (d.size() / 3 != r.count) {
                return error(Errc::parse_error,
                             what + " (accessor " + std::to_string(position->second) + ") has " +
                                 std::to_string(d.size() / 3) + " elements, POSITION " +
                                 std::to_string(r.count));
            }
            MorphTarget& t = skin_.morph_targets[it->second + k];
            for (std::uint32_t v = 0; v < r.count; ++v) {
                const glm::dvec3 delta(d[3 * v], d[3 * v + 1], d[3 * v + 2]);
                if (!std::isfinite(delta.x) || !std::isfinite(delta.y) || !std::isfinite(delta.z)) {
                    return error(Errc::numerical,
                                 what + " element " + std::to_string(v) + " is not finite");
                }
                if (delta == glm::dvec3(0.0)) continue;
                t.vertices.push_back(r.first_vertex + v);
                t.deltas.push_back(linear * delta);
            }
        }
    }
    return Status::ok();
}

Status SkinReader::channel(std::size_t a, std::size_t c, Animation& out, bool& keep) {
    keep = false;
    const tinygltf::Animation& anim = model_.animations[a];
    const tinygltf::AnimationChannel& ch = anim.channels[c];
    const std::string where = "animation " + std::to_string(a) + " channel " + std::to_string(c);
    if (ch.target_node < 0) {
        warn(where + " names no node; skipped");
        return Status::ok();
    }
    if (static_cast<std::size_t>(ch.target_node) >= model_.nodes.size()) {
        return error(Errc::out_of_range, where + ": node " + std::to_string(ch.target_node) +
                                             " does not exist (the file has " +
                                             std::to_string(model_.nodes.size()) + ")");
    }
    AnimationChannel out_ch;
    out_ch.node = static_cast<std::uint32_t>(ch.target_node);
    int type = TINYGLTF_TYPE_VEC3;
    if (ch.target_path == "translation") {
        out_ch.path = AnimationPath::translation;
        out_ch.width = 3;
    } else if (ch.target_path == "rotation") {
        out_ch.path = AnimationPath::rotation;
        out_ch.width = 4;
        type = TINYGLTF_TYPE_VEC4;
    } else if (ch.target_path == "scale") {
        out_ch.path = AnimationPath::scale;
        out_ch.width = 3;
    } else if (ch.target_path == "weights") {
        out_ch.path = AnimationPath::weights;
        type = TINYGLTF_TYPE_SCALAR;
        const int mesh = model_.nodes[ch.target_node].mesh;
        if (mesh < 0 || static_cast<std::size_t>(mesh) >= model_.meshes.size() ||
            model_.meshes[mesh].primitives.empty() ||
            model_.meshes[mesh].primitives.front().targets.empty()) {
            warn(where + " animates the weights of node " + std::to_string(ch.target_node) +
                 ", which has no morph targets; skipped");
            return Status::ok();
        }
        out_ch.width =
            static_cast<std::uint32_t>(model_.meshes[mesh].primitives.front().targets.size());
    } else {
        warn(where + ": path '" + ch.target_path + "' is not animated here; skipped");
        return Status::ok();
    }
    if (model_.nodes[ch.target_node].matrix.size() == 16 && out_ch.path != AnimationPath::weights) {
        warn(where + " animates node " + std::to_string(ch.target_node) +
             ", which has a matrix (glTF forbids it); skipped");
        return Status::ok();
    }
    if (ch.sampler < 0 || static_cast<std::size_t>(ch.sampler) >= anim.samplers.size()) {
        return error(Errc::out_of_range, where + ": sampler " + std::to_string(ch.sampler) +
                                             " does not exist (the animation has " +
                                             std::to_string(anim.samplers.size()) + ")");
    }
    const tinygltf::AnimationSampler& sampler = anim.samplers[ch.sampler];
    if (sampler.interpolation.empty() || sampler.interpolation == "LINEAR") {
        out_ch.interpolation = Interpolation::linear;
    } else if (sampler.interpolation == "STEP") {
        out_ch.interpolation = Interpolation::step;
    } else if (sampler.interpolation == "CUBICSPLINE") {
        out_ch.interpolation = Interpolation::cubic_spline;
    } else {
        return error(Errc::parse_error, where + ": interpolation '" + sampler.interpolation +
                                            "' is not LINEAR, STEP or CUBICSPLINE");
    }
    const std::string input = where + " input";
    if (Status s = check_accessor_shape(model_, sampler.input, TINYGLTF_TYPE_SCALAR, input); !s) {
        return located(s);
    }
    if (Status s = read_accessor(model_, sampler.input, 1, input, out_ch.times); !s) {
        return located(s);
    }
    for (std::size_t k = 0; k < out_ch.times.size(); ++k) {
        if (!std::isfinite(out_ch.times[k]) || (k > 0 && out_ch.times[k] < out_ch.times[k - 1])) {
            return error(Errc::parse_error, input + " key " + std::to_string(k) +
                                                ": times must be finite and ascending");
        }
    }
    const std::string output = where + " output";
    if (Status s = check_accessor_shape(model_, sampler.output, type, output); !s) {
        return located(s);
    }
    const int components = type == TINYGLTF_TYPE_SCALAR ? 1 : static_cast<int>(out_ch.width);
    if (Status s = read_accessor(model_, sampler.output, components, output, out_ch.values); !s) {
        return located(s);
    }
    const std::size_t per_key =
        (out_ch.interpolation == Interpolation::cubic_spline ? 3 : 1) * out_ch.width;
    if (out_ch.values.size() != out_ch.times.size() * per_key) {
        return error(Errc::parse_error, output + " (accessor " + std::to_string(sampler.output) +
                                            ") has " + std::to_string(out_ch.values.size()) +
                                            " values for " + std::to_string(out_ch.times.size()) +
                                            " keys of " + std::to_string(per_key));
    }
    for (std::size_t i = 0; i < out_ch.values.size(); ++i) {
        if (!std::isfinite(out_ch.values[i])) {
            return error(Errc::numerical,
                         output + " value " + std::to_string(i) + " is not finite");
        }
    }
    if (out_ch.times.empty()) {
        warn(where + " has no keys; skipped");
        return Status::ok();
    }
    if (out_ch.path == AnimationPath::weights) {
        GltfWeightSampler w;
        w.animation = static_cast<int>(a);
        w.sampler = ch.sampler;
        w.node = ch.target_node;
        w.width = out_ch.width;
        w.cubic_spline = out_ch.interpolation == Interpolation::cubic_spline;
        w.values = out_ch.values;
        asset_.weight_samplers.push_back(std::move(w));
    }
    out.start =
        out.channels.empty() ? out_ch.times.front() : std::min(out.start, out_ch.times.front());
    out.end = out.channels.empty() ? out_ch.times.back() : std::max(out.end, out_ch.times.back());
    out.channels.push_back(std::move(out_ch));
    keep = true;
    return Status::ok();
}

Status SkinReader::animations() {
    for (std::size_t a = 0; a < model_.animations.size(); ++a) {
        Animation out;
        out.name = model_.animations[a].name.empty() ? "animation_" + std::to_string(a)
                                                     : model_.animations[a].name;
        for (std::size_t c = 0; c < model_.animations[a].channels.size(); ++c) {
            bool keep = false;
            if (Status s = channel(a, c, out, keep); !s) return s;
        }
        skin_.animations.push_back(std::move(out));
    }
    return Status::ok();
}

}  // namespace

Status read_gltf_skin(const tinygltf::Model& model, std::string_view source, GltfAsset& asset,
                      Skin& skin, LoadReport& report) {
    skin = Skin{};
    SkinReader reader(model, source, asset, skin, report);
    Status s = reader.nodes();
    if (s) s = reader.joints();
    if (s) s = reader.influences();
    if (s) s = reader.morph_targets();
    if (s && (skin.joint_count() > 0 || !skin.morph_targets.empty())) s = reader.animations();
    if (!s || (skin.joint_count() == 0 && skin.morph_targets.empty())) {
        skin = Skin{};
        asset.weight_samplers.clear();
    }
    return s;
}

}  // namespace dfm::mesh
