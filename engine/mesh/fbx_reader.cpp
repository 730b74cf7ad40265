#include <algorithm>
#include <cmath>
#include <map>
#include <unordered_map>
#include <utility>

#include <assimp/config.h>
#include <assimp/scene.h>
#include <assimp/Importer.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/matrix.hpp>

#include "mesh/fbx_io.hpp"
#include "mesh/mesh_builder.hpp"

// Assimp reads the scene: the model hierarchy with each model's transform
// (pivots and pre- and post-rotations as their own nodes), the animation
// stacks resampled into keys, each mesh's polygon corners (one vertex per
// corner) with their skin weights and blend shape positions. Dualform joins
// the corners back onto the control points they came from (the file's
// PolygonVertexIndex, read by fbx_scene.cpp), checking that they agree, and
// takes from the file itself what Assimp 5.2 rounds or loses: the control
// points, shape deltas and bind poses (Transform, TransformLink) in double
// precision where Assimp keeps floats, the channels' default weights
// (DeformPercent: Assimp gives every one-shape channel weight 1), and the
// units and axes (UnitScaleFactor, which Assimp reads as a float and does
// not apply, UpAxis and FrontAxis).
namespace dfm::mesh {

namespace {

glm::dmat4 to_glm(const aiMatrix4x4& m) {
    glm::dmat4 out;
    for (unsigned r = 0; r < 4; ++r) {
        for (unsigned c = 0; c < 4; ++c) out[c][r] = m[r][c];
    }
    return out;
}

// A node's matrix as translation, rotation and scale, when it is one
// within float rounding (Assimp keeps matrices in float).
bool decompose(const glm::dmat4& m, SkeletonNode& node) {
    glm::dvec3 column[3];
    glm::dvec3 scale;
    for (int c = 0; c < 3; ++c) {
        column[c] = glm::dvec3(m[c]);
        scale[c] = glm::length(column[c]);
        if (!(scale[c] > 0.0) || !std::isfinite(scale[c])) return false;
    }
    if (glm::determinant(glm::dmat3(m)) < 0.0) scale.x = -scale.x;
    glm::dmat3 rotation;
    for (int c = 0; c < 3; ++c) rotation[c] = column[c] / scale[c];
    const glm::dquat q = glm::normalize(glm::quat_cast(rotation));
    glm::dmat4 back = glm::translate(glm::dmat4(1.0), glm::dvec3(m[3]));
    back *= glm::mat4_cast(q);
    back = glm::scale(back, scale);
    double largest = 1.0;
    for (int c = 0; c < 4; ++c) {
        for (int r = 0; r < 4; ++r) largest = std::max(largest, std::abs(m[c][r]));
    }
    for (int c = 0; c < 4; ++c) {
        for (int r = 0; r < 4; ++r) {
            if (std::abs(back[c][r] - m[c][r]) > 1e-5 * largest) return false;
        }
    }
    if (m[0][3] != 0.0 || m[1][3] != 0.0 || m[2][3] != 0.0 || m[3][3] != 1.0) return false;
    node.translation = glm::dvec3(m[3]);
    node.rotation = q;
    node.scale = scale;
    return true;
}

// Whether a quad is cut on its 1-3 diagonal rather than 0-2: where corner 1
// or 3 does not lie strictly on its own side of the 0-2 diagonal (a quad
// folded over it, or degenerate), as Blender decides for its exports
// (is_quad_flip_v3_first_third_fast_with_normal, on the float positions and
// the quad's normal from its diagonals), so a quad is split as in the glTF
// export of the same mesh.
bool quad_folds(const FbxGeometry& g, const std::vector<std::int64_t>& quad) {
    glm::vec3 c[4];
    for (int k = 0; k < 4; ++k) {
        const double* p = &g.control_points[3 * static_cast<std::size_t>(quad[k])];
        c[k] =
            glm::vec3(static_cast<float>(p[0]), static_cast<float>(p[1]), static_cast<float>(p[2]));
    }
    const glm::vec3 normal = glm::cross(c[0] - c[2], c[1] - c[3]);
    const float length = glm::length(normal);
    if (!(length > 0.0f)) return false;
    const glm::vec3 tangent = glm::cross(c[2] - c[0], normal / length);
    const float on_diagonal = glm::dot(c[0], tangent);
    return glm::dot(c[3], tangent) >= on_diagonal || glm::dot(c[1], tangent) <= on_diagonal;
}

// How far Assimp's float corners may lie from the file's control points:
// it keeps floats, and parses ASCII numbers with its own conversion, a
// rounding off ours; anything more is another corner.
double corner_tolerance(const FbxGeometry& g) {
    double largest = 0.0;
    for (double c : g.control_points) largest = std::max(largest, std::abs(c));
    return 1e-6 * largest;
}

class FbxLoader {
public:
    FbxLoader(FbxAsset& asset, std::string_view source, Mesh& host, Skin& skin, LoadReport& report)
        : asset_(asset),
          doc_(asset.document),
          scene_(asset.scene),
          source_(source),
          host_(host),
          skin_(skin),
          report_(report) {}

    Status run();

private:
    Status error(Errc code, const std::string& what) const {
        return Status(code, std::string(source_) + ": " + what);
    }
    void warn(const std::string& what) { report_.warn(std::string(source_) + ": " + what); }

    Status import();
    void nodes();
    Status model_node(const std::string& name, std::uint32_t& out) const;
    Status corners_of(const FbxGeometry& g, const aiMesh*& out) const;
    Status geometry(std::size_t index);
    Status influences(const FbxGeometry& g, const aiMesh& mesh, std::uint32_t first_vertex,
                      std::uint32_t first_joint);
    Status morph_targets(const FbxGeometry& g, const aiMesh& mesh, const FbxGeometryRange& range,
                         std::uint32_t node);
    void animations();
    void morph_animation(const aiMeshMorphAnim& channel, double ticks_per_second, Animation& out);

    FbxAsset& asset_;
    const FbxDocument& doc_;
    const FbxScene& scene_;
    std::string_view source_;
    Mesh& host_;
    Skin& skin_;
    LoadReport& report_;
    Assimp::Importer importer_;
    const aiScene* ai_ = nullptr;
    std::vector<const aiNode*> ai_nodes_;                          // per skin node
    std::unordered_map<std::string, std::uint32_t> node_by_name_;  // Assimp's names
    std::vector<InfluenceList> influences_;                        // per host vertex
    // Geometries' first morph target, by the name Assimp gives a mesh's
    // morph animation ("MODEL*0").
    std::map<std::string, std::pair<std::size_t, std::size_t>> morph_columns_;
};

Status FbxLoader::import() {
    importer_.SetPropertyBool(AI_CONFIG_IMPORT_FBX_READ_MATERIALS, false);
    importer_.SetPropertyBool(AI_CONFIG_IMPORT_FBX_READ_TEXTURES, false);
    importer_.SetPropertyBool(AI_CONFIG_IMPORT_FBX_READ_CAMERAS, false);
    importer_.SetPropertyBool(AI_CONFIG_IMPORT_FBX_READ_LIGHTS, false);
    importer_.SetPropertyBool(AI_CONFIG_IMPORT_FBX_READ_ALL_GEOMETRY_LAYERS, false);
    importer_.SetPropertyBool(AI_CONFIG_IMPORT_FBX_PRESERVE_PIVOTS, true);
    importer_.SetPropertyBool(AI_CONFIG_IMPORT_REMOVE_EMPTY_BONES, false);
    ai_ = importer_.ReadFileFromMemory(doc_.bytes.data(), doc_.bytes.size(), 0, "fbx");
    if (ai_ == nullptr || ai_->mRootNode == nullptr) {
        return error(Errc::parse_error,
                     std::string("Assimp could not read the file: ") + importer_.GetErrorString());
    }
    return Status::ok();
}

// The skin's node graph is Assimp's: a root holding the file's units and
// axes, then one node per model, or a chain of them where a model has
// pivots, offsets or pre- and post-rotations.
void FbxLoader::nodes() {
    std::vector<std::pair<const aiNode*, std::uint32_t>> stack{{ai_->mRootNode, no_index}};
    while (!stack.empty()) {
        const auto [n, parent] = stack.back();
        stack.pop_back();
        const auto index = static_cast<std::uint32_t>(skin_.nodes.size());
        SkeletonNode node;
        node.name = n->mName.C_Str();
        node.parent = parent;
        const glm::dmat4 local = to_glm(n->mTransformation);
        if (parent == no_index) {
            node.has_matrix = true;
            node.matrix = scene_.settings.to_metres_y_up * local;
        } else if (!decompose(local, node)) {
            node.has_matrix = true;
            node.matrix = local;
        }
        node_by_name_.try_emplace(node.name, index);
        skin_.nodes.push_back(std::move(node));
        ai_nodes_.push_back(n);
        for (unsigned c = n->mNumChildren; c-- > 0;) stack.push_back({n->mChildren[c], index});
    }
}

Status FbxLoader::model_node(const std::string& name, std::uint32_t& out) const {
    if (scene_.repeated_model_names.count(name) != 0) {
        return error(Errc::unsupported,
                     "more than one model is named '" + name +
                         "': Dualform finds Assimp's node of a mesh or joint by its model's "
                         "name");
    }
    const auto it = node_by_name_.find(name);
    if (it == node_by_name_.end()) {
        return error(Errc::internal, "Assimp made no node for model '" + name + "'");
    }
    out = it->second;
    return Status::ok();
}

// Assimp's mesh for `g`: one vertex per polygon corner, in the file's
// order, each at its control point's position rounded to float.
Status FbxLoader::corners_of(const FbxGeometry& g, const aiMesh*& out) const {
    out = nullptr;
    std::uint32_t node = no_index;
    if (Status s = model_node(g.model_name, node); !s) return s;
    // The node with the model's own name is the last of its chain.
    const aiNode* ai_node = ai_nodes_[node];
    const double tolerance = corner_tolerance(g);
    std::string mismatch;
    for (unsigned k = 0; ai_node != nullptr && k < ai_node->mNumMeshes; ++k) {
        if (ai_node->mMeshes[k] >= ai_->mNumMeshes) continue;
        const aiMesh* m = ai_->mMeshes[ai_node->mMeshes[k]];
        if (m->mNumVertices != g.corners.size()) continue;
        bool same = true;
        for (std::size_t c = 0; c < g.corners.size() && same; ++c) {
            const double* p = &g.control_points[3 * std::size_t{g.corners[c]}];
            const aiVector3D& q = m->mVertices[c];
            same = std::abs(p[0] - q.x) <= tolerance && std::abs(p[1] - q.y) <= tolerance &&
                   std::abs(p[2] - q.z) <= tolerance;
            if (!same) {
                mismatch = ": corner " + std::to_string(c) + " (control point " +
                           std::to_string(g.corners[c]) + ") is at another position";
            }
        }
        if (same) {
            out = m;
            return Status::ok();
        }
    }
    return error(Errc::parse_error,
                 "Assimp's reading of geometry '" + g.name + "' (model '" + g.model_name +
                     "') does not match the file's polygons" +
                     (mismatch.empty() ? " (no mesh with one vertex per corner)" : mismatch));
}

Status FbxLoader::influences(const FbxGeometry& g, const aiMesh& mesh, std::uint32_t first_vertex,
                             std::uint32_t first_joint) {
    // Each corner's (joint, weight) pairs, flat: counted, then filled.
    std::vector<std::uint32_t> bone_joint(mesh.mNumBones, no_index);
    std::vector<std::uint32_t> start(g.corners.size() + 1, 0);
    for (unsigned b = 0; b < mesh.mNumBones; ++b) {
        const aiBone& bone = *mesh.mBones[b];
        const std::string name = bone.mName.C_Str();
        for (std::size_t c = 0; c < g.clusters.size(); ++c) {
            if (g.clusters[c].model_name == name) {
                bone_joint[b] = first_joint + static_cast<std::uint32_t>(c);
                break;
            }
        }
        if (bone_joint[b] == no_index) {
            return error(Errc::parse_error, "geometry '" + g.name + "': Assimp's bone '" + name +
                                                "' matches none of its skin's clusters");
        }
        for (unsigned k = 0; k < bone.mNumWeights; ++k) {
            const aiVertexWeight& w = bone.mWeights[k];
            if (w.mVertexId >= g.corners.size() || !std::isfinite(w.mWeight) || w.mWeight < 0.0f) {
                return error(Errc::parse_error, "geometry '" + g.name + "': Assimp's bone '" +
                                                    name + "' has a weight out of range");
            }
            if (w.mWeight > 0.0f) ++start[w.mVertexId + 1];
        }
    }
    for (std::size_t c = 0; c < g.corners.size(); ++c) start[c + 1] += start[c];
    std::vector<std::pair<std::uint32_t, double>> pairs(start.back());
    std::vector<std::uint32_t> fill(start.begin(), start.end() - 1);
    for (unsigned b = 0; b < mesh.mNumBones; ++b) {
        const aiBone& bone = *mesh.mBones[b];
        for (unsigned k = 0; k < bone.mNumWeights; ++k) {
            const aiVertexWeight& w = bone.mWeights[k];
            if (w.mWeight > 0.0f) pairs[fill[w.mVertexId]++] = {bone_joint[b], w.mWeight};
        }
    }
    // Each control point takes its first corner's influences; every other
    // corner must have the same.
    std::vector<std::uint32_t> first_corner(g.control_point_count(), no_index);
    for (std::size_t c = 0; c < g.corners.size(); ++c) {
        const auto begin = pairs.begin() + start[c], end = pairs.begin() + start[c + 1];
        std::sort(begin, end);
        std::uint32_t& first = first_corner[g.corners[c]];
        if (first == no_index) {
            first = static_cast<std::uint32_t>(c);
            influences_[first_vertex + g.corners[c]].assign(begin, end);
        } else if (!std::equal(begin, end, pairs.begin() + start[first],
                               pairs.begin() + start[first + 1])) {
            return error(Errc::parse_error,
                         "geometry '" + g.name + "': Assimp gave corners " + std::to_string(first) +
                             " and " + std::to_string(c) + " of control point " +
                             std::to_string(g.corners[c]) + " different skin weights");
        }
    }
    return Status::ok();
}

Status FbxLoader::morph_targets(const FbxGeometry& g, const aiMesh& mesh,
                                const FbxGeometryRange& range, std::uint32_t node) {
    const glm::dmat3 linear(range.world);
    const double tolerance = corner_tolerance(g);
    std::size_t anim_mesh = 0;
    morph_columns_[g.model_name + "*0"] = {skin_.morph_targets.size(), g.channels.size()};
    for (std::size_t k = 0; k < g.channels.size(); ++k) {
        const FbxShapeChannel& ch = g.channels[k];
        // Assimp makes one morph mesh per shape; a channel's last is its
        // full shape. Its positions are base + delta, in float.
        anim_mesh += ch.shapes;
        const aiAnimMesh* am =
            anim_mesh - 1 < mesh.mNumAnimMeshes ? mesh.mAnimMeshes[anim_mesh - 1] : nullptr;
        if (am == nullptr || am->mVertices == nullptr || am->mNumVertices != mesh.mNumVertices) {
            return error(Errc::parse_error, "geometry '" + g.name +
                                                "': Assimp has no morph mesh for "
                                                "blend shape channel '" +
                                                ch.name + "'");
        }
        std::vector<glm::dvec3> delta(g.control_point_count(), glm::dvec3(0.0));
        for (std::size_t i = 0; i < ch.indexes.size(); ++i) {
            delta[ch.indexes[i]] =
                glm::dvec3(ch.deltas[3 * i], ch.deltas[3 * i + 1], ch.deltas[3 * i + 2]);
        }
        for (std::size_t c = 0; c < g.corners.size(); ++c) {
            const glm::dvec3& d = delta[g.corners[c]];
            const aiVector3D& base = mesh.mVertices[c];
            const aiVector3D& moved = am->mVertices[c];
            if (std::abs(base.x + d.x - moved.x) > tolerance ||
                std::abs(base.y + d.y - moved.y) > tolerance ||
                std::abs(base.z + d.z - moved.z) > tolerance) {
                return error(Errc::parse_error,
                             "geometry '" + g.name + "': Assimp's morph mesh for channel '" +
                                 ch.name + "' disagrees with its shape at corner " +
                                 std::to_string(c) + " (control point " +
                                 std::to_string(g.corners[c]) + ")");
            }
        }
        MorphTarget t;
        t.name = ch.name;
        t.node = node;
        t.column = static_cast<std::uint32_t>(k);
        t.default_weight = ch.deform_percent / 100.0;
        for (std::size_t i = 0; i < ch.indexes.size(); ++i) {
            const glm::dvec3 d(ch.deltas[3 * i], ch.deltas[3 * i + 1], ch.deltas[3 * i + 2]);
            if (d == glm::dvec3(0.0)) continue;
            t.vertices.push_back(range.first_vertex + ch.indexes[i]);
            t.deltas.push_back(linear * d);
        }
        skin_.morph_targets.push_back(std::move(t));
    }
    return Status::ok();
}

Status FbxLoader::geometry(std::size_t index) {
    const FbxGeometry& g = scene_.geometries[index];
    const aiMesh* mesh = nullptr;
    if (Status s = corners_of(g, mesh); !s) return s;
    std::uint32_t node = no_index;
    if (Status s = model_node(g.model_name, node); !s) return s;
    FbxGeometryRange range;
    range.geometry = index;
    range.first_vertex = static_cast<std::uint32_t>(host_.positions.size());
    range.count = static_cast<std::uint32_t>(g.control_point_count());
    if (!g.clusters.empty()) {
        // A skinned mesh stands where its skin was bound: the file's
        // Transform is the mesh in the joint's space at bind time, so the
        // mesh's global is TransformLink * Transform (as Blender's importer
        // and the FBX SDK take them).
        const glm::dmat4 bound = g.clusters.front().transform_link * g.clusters.front().transform;
        range.world = scene_.settings.to_metres_y_up * bound;
        double largest = 1.0;
        for (int c = 0; c < 4; ++c) {
            for (int r = 0; r < 4; ++r) largest = std::max(largest, std::abs(bound[c][r]));
        }
        for (const FbxCluster& c : g.clusters) {
            const glm::dmat4 other = c.transform_link * c.transform;
            bool same = true;
            for (int i = 0; i < 16; ++i) {
                same =
                    same && std::abs(other[i / 4][i % 4] - bound[i / 4][i % 4]) <= 1e-6 * largest;
            }
            if (!same) {
                warn("geometry '" + g.name +
                     "': its clusters disagree on the mesh's bind "
                     "transform (TransformLink * Transform); the first's is used");
                break;
            }
        }
    } else {
        glm::dmat4 global(1.0);
        std::vector<std::uint32_t> chain;
        for (std::uint32_t at = node; at != no_index; at = skin_.nodes[at].parent) {
            chain.push_back(at);
        }
        for (auto it = chain.rbegin(); it != chain.rend(); ++it) {
            const SkeletonNode& n = skin_.nodes[*it];
            glm::dmat4 local = n.matrix;
            if (!n.has_matrix) {
                local = glm::translate(glm::dmat4(1.0), n.translation) * glm::mat4_cast(n.rotation);
                local = glm::scale(local, n.scale);
            }
            global *= local;
        }
        range.world = global;
    }
    MeshBuilder builder(report_);
    const Where at_vertices = doc_.where(doc_.nodes[g.vertices_node]);
    for (std::size_t v = 0; v < g.control_point_count(); ++v) {
        const glm::dvec3 p(g.control_points[3 * v], g.control_points[3 * v + 1],
                           g.control_points[3 * v + 2]);
        const glm::dvec3 world = glm::dvec3(range.world * glm::dvec4(p, 1.0));
        if (Status s = builder.add_vertex(world, at_vertices); !s) return s;
    }
    const Where at_polygons = doc_.where(*doc_.child(g.node, "PolygonVertexIndex"));
    std::vector<std::int64_t> corners;
    std::size_t short_polygons = 0;
    for (std::size_t p = 0; p < g.polygon_count(); ++p) {
        corners.assign(g.corners.begin() + g.polygon_start[p],
                       g.corners.begin() + g.polygon_start[p + 1]);
        if (corners.size() < 3) {
            ++short_polygons;
            continue;
        }
        // A quad folded over its 0-2 diagonal (corners 1 and 3 on the same
        // side of it) is cut on 1-3 instead, as Blender cuts it: fanned from
        // corner 1.
        if (corners.size() == 4 && quad_folds(g, corners)) {
            std::rotate(corners.begin(), corners.begin() + 1, corners.end());
        }
        if (Status s = builder.add_polygon(corners, at_polygons); !s) return s;
    }
    if (short_polygons > 0) {
        warn("geometry '" + g.name + "': " + std::to_string(short_polygons) +
             " polygons of fewer than 3 corners (points or edges) are not a surface; skipped");
    }
    const Mesh part = builder.take();
    if (host_.positions.size() + part.positions.size() >= no_index) {
        return error(Errc::out_of_range, "more vertices than 32-bit indices address");
    }
    for (const Triangle& t : part.triangles) {
        host_.triangles.push_back(
            {t[0] + range.first_vertex, t[1] + range.first_vertex, t[2] + range.first_vertex});
    }
    host_.positions.insert(host_.positions.end(), part.positions.begin(), part.positions.end());
    influences_.resize(host_.positions.size());
    if (!g.clusters.empty()) {
        const auto first_joint = static_cast<std::uint32_t>(skin_.joint_count());
        const glm::dmat4 to_file = glm::inverse(scene_.settings.to_metres_y_up);
        for (const FbxCluster& c : g.clusters) {
            std::uint32_t joint_node = no_index;
            if (c.model != 0) {
                if (Status s = model_node(c.model_name, joint_node); !s) return s;
            } else {
                warn("geometry '" + g.name +
                     "': a skin cluster binds no model; its joint "
                     "stays where it was bound");
            }
            skin_.joint_names.push_back(c.model_name);
            skin_.joint_nodes.push_back(joint_node);
            // Joint world matrices include the root's units and axes.
            skin_.inverse_bind.push_back(glm::inverse(c.transform_link) * to_file);
        }
        if (Status s = influences(g, *mesh, range.first_vertex, first_joint); !s) return s;
    }
    if (!g.channels.empty()) {
        if (Status s = morph_targets(g, *mesh, range, node); !s) return s;
    }
    asset_.ranges.push_back(range);
    return Status::ok();
}

void FbxLoader::morph_animation(const aiMeshMorphAnim& channel, double ticks_per_second,
                                Animation& out) {
    const auto it = morph_columns_.find(channel.mName.C_Str());
    if (it == morph_columns_.end()) {
        warn(std::string("animation '") + out.name + "': morph weights of '" +
             channel.mName.C_Str() + "', no mesh that was loaded; skipped");
        return;
    }
    const auto [first_target, width] = it->second;
    // Each column's own keys (FBX animates channels apart), then every
    // column sampled linearly at the union of their times.
    std::vector<std::vector<std::pair<double, double>>> keys(width);
    std::vector<double> times;
    for (unsigned k = 0; k < channel.mNumKeys; ++k) {
        const aiMeshMorphKey& key = channel.mKeys[k];
        const double t = key.mTime / ticks_per_second;
        if (!std::isfinite(t)) continue;
        for (unsigned i = 0; i < key.mNumValuesAndWeights; ++i) {
            if (key.mValues[i] >= width || !std::isfinite(key.mWeights[i])) continue;
            keys[key.mValues[i]].push_back({t, key.mWeights[i]});
            times.push_back(t);
        }
    }
    std::sort(times.begin(), times.end());
    times.erase(std::unique(times.begin(), times.end()), times.end());
    if (times.empty()) return;
    AnimationChannel ch;
    ch.node = skin_.morph_targets[first_target].node;
    ch.path = AnimationPath::weights;
    ch.width = static_cast<std::uint32_t>(width);
    ch.times = times;
    for (auto& column : keys) std::sort(column.begin(), column.end());
    for (double t : times) {
        for (std::size_t c = 0; c < width; ++c) {
            const auto& column = keys[c];
            double v = skin_.morph_targets[first_target + c].default_weight;
            if (!column.empty()) {
                const auto after = std::lower_bound(column.begin(), column.end(),
                                                    std::pair<double, double>{t, -INFINITY});
                if (after == column.begin()) {
                    v = column.front().second;
                } else if (after == column.end()) {
                    v = column.back().second;
                } else {
                    const auto before = after - 1;
                    const double u = (t - before->first) / (after->first - before->first);
                    v = before->second + u * (after->second - before->second);
                }
            }
            ch.values.push_back(v);
        }
    }
    out.start = out.channels.empty() ? times.front() : std::min(out.start, times.front());
    out.end = out.channels.empty() ? times.back() : std::max(out.end, times.back());
    out.channels.push_back(std::move(ch));
}

void FbxLoader::animations() {
    for (unsigned a = 0; a < ai_->mNumAnimations; ++a) {
        const aiAnimation& anim = *ai_->mAnimations[a];
        Animation out;
        out.name = anim.mName.length > 0 ? anim.mName.C_Str() : "animation_" + std::to_string(a);
        const double tps = anim.mTicksPerSecond;
        if (!(tps > 0.0) || !std::isfinite(tps)) {
            warn("animation '" + out.name + "' has no frame rate; skipped");
            continue;
        }
        const auto add = [&](AnimationChannel ch) {
            if (ch.times.empty()) return;
            for (std::size_t k = 0; k < ch.times.size(); ++k) {
                if (!std::isfinite(ch.times[k]) || (k > 0 && ch.times[k] < ch.times[k - 1])) {
                    warn("animation '" + out.name + "': a channel of node '" +
                         skin_.nodes[ch.node].name + "' has keys out of order; skipped");
                    return;
                }
            }
            for (double v : ch.values) {
                if (!std::isfinite(v)) {
                    warn("animation '" + out.name + "': a channel of node '" +
                         skin_.nodes[ch.node].name + "' has a value that is not finite; skipped");
                    return;
                }
            }
            out.start =
                out.channels.empty() ? ch.times.front() : std::min(out.start, ch.times.front());
            out.end = out.channels.empty() ? ch.times.back() : std::max(out.end, ch.times.back());
            out.channels.push_back(std::move(ch));
        };
        for (unsigned c = 0; c < anim.mNumChannels; ++c) {
            const aiNodeAnim& na = *anim.mChannels[c];
            const auto it = node_by_name_.find(na.mNodeName.C_Str());
            if (it == node_by_name_.end() || skin_.nodes[it->second].has_matrix) {
                warn("animation '" + out.name + "' animates node '" + na.mNodeName.C_Str() + "', " +
                     (it == node_by_name_.end() ? "which Assimp did not make"
                                                : "whose matrix is not translation, rotation "
                                                  "and scale") +
                     "; skipped");
                continue;
            }
            AnimationChannel t, r, s;
            t.node = r.node = s.node = it->second;
            t.path = AnimationPath::translation;
            r.path = AnimationPath::rotation;
            s.path = AnimationPath::scale;
            t.width = s.width = 3;
            r.width = 4;
            for (unsigned k = 0; k < na.mNumPositionKeys; ++k) {
                const aiVectorKey& key = na.mPositionKeys[k];
                t.times.push_back(key.mTime / tps);
                t.values.insert(t.values.end(), {key.mValue.x, key.mValue.y, key.mValue.z});
            }
            for (unsigned k = 0; k < na.mNumRotationKeys; ++k) {
                const aiQuatKey& key = na.mRotationKeys[k];
                r.times.push_back(key.mTime / tps);
                r.values.insert(r.values.end(),
                                {key.mValue.x, key.mValue.y, key.mValue.z, key.mValue.w});
            }
            for (unsigned k = 0; k < na.mNumScalingKeys; ++k) {
                const aiVectorKey& key = na.mScalingKeys[k];
                s.times.push_back(key.mTime / tps);
                s.values.insert(s.values.end(), {key.mValue.x, key.mValue.y, key.mValue.z});
            }
            add(std::move(t));
            add(std::move(r));
            add(std::move(s));
        }
        for (unsigned c = 0; c < anim.mNumMorphMeshChannels; ++c) {
            morph_animation(*anim.mMorphMeshChannels[c], tps, out);
        }
        skin_.animations.push_back(std::move(out));
    }
}

Status FbxLoader::run() {
    if (Status s = import(); !s) return s;
    nodes();
    for (std::size_t g = 0; g < scene_.geometries.size(); ++g) {
        if (Status s = geometry(g); !s) return s;
    }
    if (host_.triangles.empty()) {
        return error(Errc::parse_error, "no polygon of 3 or more corners in the scene's meshes");
    }
    if (skin_.joint_count() == 0 && skin_.morph_targets.empty()) {
        skin_ = Skin{};
        return Status::ok();
    }
    const std::size_t unweighted = static_cast<std::size_t>(
        std::count_if(influences_.begin(), influences_.end(),
                      [](const InfluenceList& list) { return list.empty(); }));
    set_influences(influences_, skin_);
    if (skin_.joint_count() > 0 && unweighted > 0) {
        warn(std::to_string(unweighted) +
             " control points have no skin weight; posed, they stay where they are bound");
    }
    animations();
    return Status::ok();
}

}  // namespace

Status read_fbx(std::string bytes, std::string_view source, Mesh& host, FbxAsset& asset, Skin& skin,
                LoadReport& report) {
    host = Mesh{};
    asset = FbxAsset{};
    skin = Skin{};
    Status s = parse_fbx(std::move(bytes), std::string(source), asset.document);
    if (s) s = scan_fbx(asset.document, asset.scene, report);
    if (s && asset.scene.geometries.empty()) {
        s = Status(Errc::parse_error, std::string(source) +
                                          ": no mesh in the scene (no Geometry of class Mesh "
                                          "under a model connected to the root)");
    }
    if (s) s = FbxLoader(asset, source, host, skin, report).run();
    if (!s) {
        host = Mesh{};
        asset = FbxAsset{};
        skin = Skin{};
    }
    return s;
}

}  // namespace dfm::mesh
