#include <cmath>
#include <map>
#include <tuple>

#include <glm/geometric.hpp>
#include <glm/matrix.hpp>

#include "mesh/fbx_binary_writer.hpp"
#include "mesh/fbx_io.hpp"
#include "mesh/fbx_values.hpp"

// An edit written back into the file it was loaded from: the tree is copied
// node by node (fbx_binary_writer.hpp) and only what the edit changes is
// encoded anew.
namespace dfm::mesh {

namespace {

// One geometry's control points after the edit, in its own space.
struct GeometryEdit {
    const FbxGeometryRange* range = nullptr;
    std::vector<glm::dvec3> points;  // every control point, moved or not
    std::vector<bool> moved;
    bool any = false;
};

// Pointers from document nodes to their copies (valid until a copy's
// children change).
void map_nodes(const FbxDocument& doc, std::uint32_t index, FbxOutNode& copy,
               std::vector<FbxOutNode*>& out) {
    out[index] = &copy;
    const FbxNode& n = doc.nodes[index];
    for (std::size_t i = 0; i < n.children.size(); ++i) {
        map_nodes(doc, n.children[i], copy.children[i], out);
    }
}

std::string_view text_child(const FbxDocument& doc, const FbxNode& node, std::string_view name) {
    const FbxNode* c = doc.child(doc.index_of(node), name);
    if (c == nullptr || c->property_count == 0) return {};
    return fbx_string(doc, doc.property(*c, 0)).value_or(std::string_view());
}

// The normals of one LayerElementNormal after the edit: where a control
// point is dirty (moved, or on a polygon with a moved one), its corners'
// normals are recomputed from the area-weighted normals of their polygons,
// corners that shared a normal before (one smooth fan) sharing one after.
// Other mappings than by polygon vertex and by control point are kept.
Status update_normals(const FbxDocument& doc, const FbxGeometry& g, const GeometryEdit& e,
                      const FbxNode& element, std::vector<FbxOutNode*>& copies) {
    const std::string_view mapping = text_child(doc, element, "MappingInformationType");
    const std::string_view reference = text_child(doc, element, "ReferenceInformationType");
    const bool by_corner = mapping == "ByPolygonVertex";
    const bool by_point =
        mapping == "ByVertice" || mapping == "ByVertex" || mapping == "ByControlPoint";
    const FbxNode* data = doc.child(doc.index_of(element), "Normals");
    if ((!by_corner && !by_point) || data == nullptr) return Status::ok();
    const FbxNode* index_node = doc.child(doc.index_of(element), "NormalsIndex");
    const bool indexed = reference == "IndexToDirect" && index_node != nullptr;
    std::vector<double> normals;
    if (Status s = fbx_doubles(doc, *data, normals); !s) return s;
    std::vector<std::int64_t> index;
    if (indexed) {
        if (Status s = fbx_integers(doc, *index_node, index); !s) return s;
    }
    const std::size_t points = g.control_point_count();
    std::vector<bool> dirty = e.moved;
    std::vector<glm::dvec3> face(g.polygon_count(), glm::dvec3(0.0));
    for (std::size_t p = 0; p < g.polygon_count(); ++p) {
        const std::uint32_t first = g.polygon_start[p], end = g.polygon_start[p + 1];
        bool touched = false;
        for (std::uint32_t c = first; c < end; ++c) touched = touched || e.moved[g.corners[c]];
        if (touched) {
            for (std::uint32_t c = first; c < end; ++c) dirty[g.corners[c]] = true;
        }
        const glm::dvec3 a = e.points[g.corners[first]];
        for (std::uint32_t c = first + 1; c + 1 < end; ++c) {
            face[p] += glm::cross(e.points[g.corners[c]] - a, e.points[g.corners[c + 1]] - a);
        }
    }
    const std::size_t slots = by_corner ? g.corners.size() : points;
    const auto slot_of = [&](std::size_t k) -> std::size_t {
        return indexed ? static_cast<std::size_t>(index[k]) : k;
    };
    // A corner without a normal (index -1) groups with none.
    const auto old_normal = [&](std::size_t k) {
        if (indexed && index[k] < 0) return glm::dvec3(std::nan(""));
        const std::size_t i = slot_of(k);
        return glm::dvec3(normals[3 * i], normals[3 * i + 1], normals[3 * i + 2]);
    };
    // Each dirty slot's sum of face normals, over the faces of its group.
    std::vector<glm::dvec3> sum(slots, glm::dvec3(0.0));
    std::vector<std::uint32_t> polygon_of(g.corners.size());
    for (std::size_t p = 0; p < g.polygon_count(); ++p) {
        for (std::uint32_t c = g.polygon_start[p]; c < g.polygon_start[p + 1]; ++c) {
            polygon_of[c] = static_cast<std::uint32_t>(p);
        }
    }
    if (by_point) {
        for (std::size_t c = 0; c < g.corners.size(); ++c) {
            if (dirty[g.corners[c]]) sum[g.corners[c]] += face[polygon_of[c]];
        }
    } else {
        // Group a point's corners by their old normal: a smooth fan shares one.
        std::vector<std::vector<std::uint32_t>> corners_of(points);
        for (std::size_t c = 0; c < g.corners.size(); ++c) {
            if (dirty[g.corners[c]])
                corners_of[g.corners[c]].push_back(static_cast<std::uint32_t>(c));
        }
        for (const std::vector<std::uint32_t>& list : corners_of) {
            for (std::uint32_t c : list) {
                for (std::uint32_t d : list) {
                    if (old_normal(c) == old_normal(d)) sum[c] += face[polygon_of[d]];
                }
            }
        }
    }
    bool changed = false;
    std::map<std::tuple<double, double, double>, std::int32_t> appended;
    for (std::size_t k = 0; k < slots; ++k) {
        const std::uint32_t point = by_corner ? g.corners[k] : static_cast<std::uint32_t>(k);
        if (!dirty[point]) continue;
        const double length = glm::length(sum[k]);
        if (!(length > 0.0) || !std::isfinite(length)) continue;
        const glm::dvec3 n = sum[k] / length;
        changed = true;
        if (indexed) {
            const auto key = std::make_tuple(n.x, n.y, n.z);
            auto [it, added] =
                appended.try_emplace(key, static_cast<std::int32_t>(normals.size() / 3));
            if (added) normals.insert(normals.end(), {n.x, n.y, n.z});
            index[k] = it->second;
        } else {
            normals[3 * k] = n.x;
            normals[3 * k + 1] = n.y;
            normals[3 * k + 2] = n.z;
        }
    }
    if (!changed) return Status::ok();
    FbxOutNode& data_copy = *copies[doc.index_of(*data)];
    data_copy.properties.clear();
    data_copy.property_count = 0;
    data_copy.add_double_array(normals);
    if (indexed) {
        std::vector<std::int32_t> narrow(index.begin(), index.end());
        FbxOutNode& index_copy = *copies[doc.index_of(*index_node)];
        index_copy.properties.clear();
        index_copy.property_count = 0;
        index_copy.add_int32_array(narrow);
    }
    return Status::ok();
}

// Adds `by` to the Count of ObjectType `type` in Definitions (making the
// ObjectType where there is none) and to Definitions' own Count.
void count_definitions(const FbxDocument& doc, const FbxScene& scene, std::string_view type,
                       std::int32_t by, std::vector<FbxOutNode*>& copies,
                       std::vector<FbxOutNode>& appended_types) {
    if (scene.definitions_node == no_index || by == 0) return;
    const FbxNode& definitions = doc.nodes[scene.definitions_node];
    const auto bump = [&](const FbxNode& count) {
        const std::optional<std::int64_t> v =
            count.property_count == 1 ? fbx_integer(doc, doc.property(count, 0)) : std::nullopt;
        if (!v) return;
        FbxOutNode& copy = *copies[doc.index_of(count)];
        copy.properties.clear();
        copy.property_count = 0;
        copy.add_int32(static_cast<std::int32_t>(*v + by));
    };
    if (const FbxNode* total = doc.child(scene.definitions_node, "Count")) bump(*total);
    for (std::uint32_t c : definitions.children) {
        const FbxNode& n = doc.nodes[c];
        if (n.name != "ObjectType" || n.property_count == 0 ||
            fbx_string(doc, doc.property(n, 0)) != type) {
            continue;
        }
        if (const FbxNode* count = doc.child(c, "Count")) bump(*count);
        return;
    }
    FbxOutNode object_type = FbxOutNode::named("ObjectType");
    object_type.add_string(type);
    object_type.add_child("Count").add_int32(by);
    appended_types.push_back(std::move(object_type));
}

std::string object_name(std::string_view name, std::string_view cls) {
    std::string out(name);
    out += std::string_view("\0\1", 2);
    out += cls;
    return out;
}

FbxOutNode connection(std::int64_t source, std::int64_t destination) {
    FbxOutNode c = FbxOutNode::named("C");
    c.add_string("OO").add_int64(source).add_int64(destination);
    return c;
}

}  // namespace

Status write_fbx(const FbxAsset& asset, std::span<const glm::dvec3> host_positions,
                 const std::string& morph_target, const std::string& pose_record,
                 std::string& out) {
    const FbxDocument& doc = asset.document;
    const FbxScene& scene = asset.scene;
    if (!doc.binary) {
        return Status(Errc::unsupported,
                      "the mesh came from an ASCII FBX file: ASCII FBX is read but not written "
                      "back (save to binary FBX from a binary file, or to another format)");
    }
    std::size_t total = 0;
    for (const FbxGeometryRange& r : asset.ranges) total += r.count;
    if (host_positions.size() != total) {
        return Status(Errc::internal, "the mesh has " + std::to_string(host_positions.size()) +
                                          " host vertices, its FBX asset " + std::to_string(total) +
                                          " control points");
    }
    std::vector<GeometryEdit> edits;
    for (const FbxGeometryRange& r : asset.ranges) {
        const FbxGeometry& g = scene.geometries[r.geometry];
        GeometryEdit e;
        e.range = &r;
        e.points.resize(r.count);
        e.moved.assign(r.count, false);
        const glm::dmat4 inverse = glm::inverse(r.world);
        for (std::uint32_t v = 0; v < r.count; ++v) {
            const glm::dvec3 p(g.control_points[3 * v], g.control_points[3 * v + 1],
                               g.control_points[3 * v + 2]);
            e.points[v] = p;
            const glm::dvec3 rest = glm::dvec3(r.world * glm::dvec4(p, 1.0));
            const glm::dvec3& now = host_positions[r.first_vertex + v];
            if (rest == now) continue;
            if (!std::isfinite(now.x) || !std::isfinite(now.y) || !std::isfinite(now.z)) {
                return Status(Errc::numerical, "host vertex " + std::to_string(r.first_vertex + v) +
                                                   " is not finite");
            }
            e.points[v] = glm::dvec3(inverse * glm::dvec4(now, 1.0));
            e.moved[v] = e.points[v] != p;
            e.any = e.any || e.moved[v];
        }
        edits.push_back(std::move(e));
    }

    std::vector<FbxOutNode> roots = fbx_out_tree(doc);
    std::vector<FbxOutNode*> copies(doc.nodes.size(), nullptr);
    for (std::size_t i = 0; i < doc.roots.size(); ++i)
        map_nodes(doc, doc.roots[i], roots[i], copies);

    if (morph_target.empty()) {
        for (const GeometryEdit& e : edits) {
            if (!e.any) continue;
            const FbxGeometry& g = scene.geometries[e.range->geometry];
            std::vector<double> flat;
            flat.reserve(3 * e.points.size());
            for (const glm::dvec3& p : e.points) flat.insert(flat.end(), {p.x, p.y, p.z});
            FbxOutNode& vertices = *copies[g.vertices_node];
            vertices.properties.clear();
            vertices.property_count = 0;
            vertices.add_double_array(flat);
            for (std::uint32_t c : doc.nodes[g.node].children) {
                if (doc.nodes[c].name != "LayerElementNormal") continue;
                if (Status s = update_normals(doc, g, e, doc.nodes[c], copies); !s) return s;
            }
        }
        out = encode_fbx(doc, roots, doc.version);
        return Status::ok();
    }

    // A blend shape channel per geometry the edit moves.
    std::vector<FbxOutNode> objects, links, types;
    std::int32_t shapes = 0, deformers = 0;
    std::int64_t next_id = static_cast<std::int64_t>(scene.largest_id) + 1;
    for (const GeometryEdit& e : edits) {
        if (!e.any) continue;
        const FbxGeometry& g = scene.geometries[e.range->geometry];
        std::vector<std::int32_t> indexes;
        std::vector<double> deltas;
        for (std::uint32_t v = 0; v < e.points.size(); ++v) {
            if (!e.moved[v]) continue;
            const glm::dvec3 d =
                e.points[v] - glm::dvec3(g.control_points[3 * v], g.control_points[3 * v + 1],
                                         g.control_points[3 * v + 2]);
            indexes.push_back(static_cast<std::int32_t>(v));
            deltas.insert(deltas.end(), {d.x, d.y, d.z});
        }
        const std::int64_t shape_id = next_id++;
        const std::int64_t channel_id = next_id++;
        std::int64_t blend_shape_id = static_cast<std::int64_t>(g.blend_shape);
        if (g.blend_shape_node == no_index) {
            blend_shape_id = next_id++;
            FbxOutNode bs = FbxOutNode::named("Deformer");
            bs.add_int64(blend_shape_id)
                .add_string(object_name(g.name, "Deformer"))
                .add_string("BlendShape");
            bs.add_child("Version").add_int32(100);
            objects.push_back(std::move(bs));
            links.push_back(connection(blend_shape_id, static_cast<std::int64_t>(g.id)));
            ++deformers;
        }
        FbxOutNode shape = FbxOutNode::named("Geometry");
        shape.add_int64(shape_id)
            .add_string(object_name(morph_target, "Geometry"))
            .add_string("Shape");
        shape.add_child("Properties70").null_record = true;
        shape.add_child("Version").add_int32(100);
        shape.add_child("Indexes").add_int32_array(indexes);
        shape.add_child("Vertices").add_double_array(deltas);
        shape.add_child("Normals").add_double_array(std::vector<double>(deltas.size(), 0.0));
        objects.push_back(std::move(shape));

        FbxOutNode channel = FbxOutNode::named("Deformer");
        channel.add_int64(channel_id)
            .add_string(object_name(morph_target, "SubDeformer"))
            .add_string("BlendShapeChannel");
        channel.add_child("Version").add_int32(100);
        channel.add_child("DeformPercent").add_double(0.0);
        // One full weight per index, as Blender writes them (its importer
        // wants one, or one per index).
        channel.add_child("FullWeights")
            .add_double_array(std::vector<double>(indexes.size(), 100.0));
        if (!pose_record.empty()) {
            FbxOutNode& props = channel.add_child("Properties70");
            props.add_child("P")
                .add_string("dualform_pose")
                .add_string("KString")
                .add_string("")
                .add_string("U")
                .add_string(pose_record);
        }
        objects.push_back(std::move(channel));
        links.push_back(connection(shape_id, channel_id));
        links.push_back(connection(channel_id, blend_shape_id));
        ++shapes;
        ++deformers;
    }
    count_definitions(doc, scene, "Geometry", shapes, copies, types);
    count_definitions(doc, scene, "Deformer", deformers, copies, types);
    // Appending invalidates the copies' pointers: done last, a new root
    // after everything else.
    if (scene.definitions_node != no_index) {
        FbxOutNode& definitions = *copies[scene.definitions_node];
        for (FbxOutNode& t : types) definitions.children.push_back(std::move(t));
    }
    FbxOutNode& objects_copy = *copies[scene.objects_node];
    for (FbxOutNode& n : objects) objects_copy.children.push_back(std::move(n));
    if (scene.connections_node != no_index) {
        FbxOutNode& connections_copy = *copies[scene.connections_node];
        for (FbxOutNode& n : links) connections_copy.children.push_back(std::move(n));
    } else if (!links.empty()) {
        FbxOutNode list = FbxOutNode::named("Connections");
        list.children = std::move(links);
        roots.push_back(std::move(list));
    }
    out = encode_fbx(doc, roots, doc.version);
    return Status::ok();
}

}  // namespace dfm::mesh
