#include "mesh/fbx_scene.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>
#include <unordered_map>

#include <glm/matrix.hpp>

#include "mesh/fbx_values.hpp"

namespace dfm::mesh {

const FbxNode* fbx_p(const FbxDocument& doc, const FbxNode* properties70, std::string_view name) {
    if (properties70 == nullptr) return nullptr;
    for (std::uint32_t c : properties70->children) {
        const FbxNode& p = doc.nodes[c];
        if (p.name != "P" || p.property_count == 0) continue;
        if (fbx_string(doc, doc.property(p, 0)) == name) return &p;
    }
    return nullptr;
}

namespace {

struct Connection {
    std::string_view type;  // "OO", "OP", ...
    std::uint64_t source = 0;
    std::uint64_t destination = 0;
};

class Scanner {
public:
    Scanner(const FbxDocument& doc, FbxScene& scene, LoadReport& report)
        : doc_(doc), scene_(scene), report_(report) {}

    Status run();

private:
    void warn(const FbxNode& node, const std::string& what) {
        report_.warn(doc_.where(node).prefix() + "node " + doc_.path(node) + ": " + what);
    }
    Status error(Errc code, const FbxNode& node, const std::string& what) const {
        return doc_.error(code, node, what);
    }

    Status arrays();
    Status property_entry(const FbxNode& p) const;
    Status property_entries();
    Status animation_curve(const FbxNode& curve) const;
    Status header();
    Status settings();
    Status objects();
    Status connections();
    Status model_hierarchy();
    Status geometry(const FbxNode& node, FbxGeometry& out);
    Status polygons(const FbxNode& geometry, FbxGeometry& out);
    Status layers(const FbxNode& geometry, const FbxGeometry& g);
    Status layer_element(const FbxNode& element, const FbxGeometry& g);
    Status skin(const FbxNode& skin, FbxGeometry& g);
    Status cluster(const FbxNode& node, const FbxGeometry& g, FbxCluster& out);
    Status blend_shape(const FbxNode& blend_shape, FbxGeometry& g);
    Status matrix(const FbxNode& owner, std::string_view name, glm::dmat4& out) const;
    std::optional<std::uint64_t> id(const FbxProperty& p) const;
    Status indexes(const FbxNode& owner, std::string_view name, std::size_t limit,
                   std::vector<std::uint32_t>& out) const;

    const FbxNode* object(std::uint64_t id) const {
        const auto it = objects_.find(id);
        return it == objects_.end() ? nullptr : &doc_.nodes[it->second];
    }
    std::string_view class_of(const FbxNode& n) const {
        if (n.property_count < 3) return {};
        return fbx_string(doc_, doc_.property(n, 2)).value_or(std::string_view());
    }
    std::string name_of(const FbxNode& n) const {
        if (n.property_count < 2) return {};
        return std::string(
            fbx_object_name(fbx_string(doc_, doc_.property(n, 1)).value_or(std::string_view())));
    }
    // The objects connected (object to object) into `destination`, in the
    // file's order, of node name `kind` and class `cls` (empty: any). As
    // Assimp takes them, every connection but an object-to-property one
    // links objects, whatever its type says.
    std::vector<std::uint64_t> sources(std::uint64_t destination, std::string_view kind,
                                       std::string_view cls) const {
        std::vector<std::uint64_t> out;
        const auto [first, last] = into_.equal_range(destination);
        for (auto it = first; it != last; ++it) {
            const Connection& c = connections_[it->second];
            if (c.type == "OP") continue;
            const FbxNode* n = object(c.source);
            if (n == nullptr || n->name != kind || (!cls.empty() && class_of(*n) != cls)) continue;
            out.push_back(c.source);
        }
        return out;
    }
    // The objects `source` connects into (object to object), in the file's
    // order, of node name `kind`.
    std::vector<std::uint64_t> destinations(std::uint64_t source, std::string_view kind) const {
        std::vector<std::uint64_t> out;
        const auto [first, last] = out_of_.equal_range(source);
        for (auto it = first; it != last; ++it) {
            const Connection& c = connections_[it->second];
            if (c.type == "OP") continue;
            const FbxNode* n = object(c.destination);
            if (n != nullptr && n->name == kind) out.push_back(c.destination);
        }
        return out;
    }

    const FbxDocument& doc_;
    FbxScene& scene_;
    LoadReport& report_;
    std::unordered_map<std::uint64_t, std::uint32_t> objects_;  // id -> node
    std::vector<Connection> connections_;
    std::multimap<std::uint64_t, std::size_t> into_;    // destination -> connection
    std::multimap<std::uint64_t, std::size_t> out_of_;  // source -> connection
    std::set<std::uint64_t> scene_models_;              // reached from the root
};

Status Scanner::arrays() {
    if (!doc_.binary) return Status::ok();
    for (const FbxNode& node : doc_.nodes) {
        for (std::uint32_t i = 0; i < node.property_count; ++i) {
            if (Status s = fbx_check_array(doc_, node, doc_.property(node, i)); !s) return s;
        }
    }
    return Status::ok();
}

Status Scanner::settings() {
    FbxSettings& s = scene_.settings;
    const FbxNode* global = doc_.child(no_index, "GlobalSettings");
    if (global == nullptr) return Status::ok();
    const FbxNode* props = doc_.child(doc_.index_of(*global), "Properties70");
    const auto read = [&](std::string_view name, double& value) -> Status {
        const FbxNode* p = fbx_p(doc_, props, name);
        if (p == nullptr) return Status::ok();
        const std::optional<double> v =
            p->property_count >= 5 ? fbx_number(doc_, doc_.property(*p, 4)) : std::nullopt;
        if (!v || !std::isfinite(*v)) {
            return error(Errc::parse_error, *p, std::string(name) + " has no finite number");
        }
        value = *v;
        return Status::ok();
    };
    double up = s.up_axis, up_sign = s.up_sign, front = s.front_axis, front_sign = s.front_sign;
    double unit = s.centimetres_per_unit;
    for (const auto& [name, value] : {std::pair<std::string_view, double*>{"UpAxis", &up},
                                      {"UpAxisSign", &up_sign},
                                      {"FrontAxis", &front},
                                      {"FrontAxisSign", &front_sign},
                                      {"UnitScaleFactor", &unit}}) {
        if (Status st = read(name, *value); !st) return st;
    }
    const auto axis = [](double a) { return a == 0.0 || a == 1.0 || a == 2.0; };
    const auto sign = [](double a) { return a == 1.0 || a == -1.0; };
    if (!axis(up) || !axis(front) || up == front || !sign(up_sign) || !sign(front_sign)) {
        return error(Errc::parse_error, *global,
                     "UpAxis " + std::to_string(up) + " (sign " + std::to_string(up_sign) +
                         ") and FrontAxis " + std::to_string(front) + " (sign " +
                         std::to_string(front_sign) +
                         ") are not two different axes 0, 1 or 2 with signs 1 or -1");
    }
    if (!(unit > 0.0)) {
        return error(Errc::parse_error, *global,
                     "UnitScaleFactor " + std::to_string(unit) + " is not positive");
    }
    s.up_axis = static_cast<int>(up);
    s.up_sign = static_cast<int>(up_sign);
    s.front_axis = static_cast<int>(front);
    s.front_sign = static_cast<int>(front_sign);
    s.centimetres_per_unit = unit;
    glm::dvec3 u(0.0), f(0.0);
    u[s.up_axis] = s.up_sign;
    f[s.front_axis] = s.front_sign;
    const glm::dvec3 r = glm::cross(u, f);
    // Rows r, u, f: the file's right, up and front become x, y and z.
    const double k = unit / 100.0;
    glm::dmat4 m(1.0);
    for (int c = 0; c < 3; ++c) {
        m[c][0] = r[c] * k;
        m[c][1] = u[c] * k;
        m[c][2] = f[c] * k;
    }
    s.to_metres_y_up = m;
    return Status::ok();
}

// An object id as Assimp takes one: a 64-bit integer property in binary
// ('L'), digits in ASCII (Assimp reads them unsigned).
std::optional<std::uint64_t> Scanner::id(const FbxProperty& p) const {
    if (doc_.binary ? p.type != 'L' : p.type != 'n') return std::nullopt;
    // Assimp's text conversion throws on anything but a digit first.
    if (!doc_.binary && !(doc_.bytes[p.begin] >= '0' && doc_.bytes[p.begin] <= '9')) {
        return std::nullopt;
    }
    const std::optional<std::int64_t> v = fbx_integer(doc_, p);
    if (!v || (!doc_.binary && *v < 0)) return std::nullopt;
    return static_cast<std::uint64_t>(*v);
}

// What Assimp's property tables require of a "P" entry (it throws, and
// leaks, where one is otherwise): a name and type string, and by the type
// enough values of the kinds it parses (FBXProperties.cpp).
Status Scanner::property_entry(const FbxNode& p) const {
    const auto string_at = [&](std::uint32_t i) {
        return i < p.property_count && fbx_string(doc_, doc_.property(p, i)).has_value();
    };
    const auto integer_at = [&](std::uint32_t i, char binary_type) {
        if (i >= p.property_count) return false;
        const FbxProperty& v = doc_.property(p, i);
        if (doc_.binary) return v.type == binary_type;
        return fbx_integer(doc_, v).has_value();
    };
    const auto number_at = [&](std::uint32_t i) {
        if (i >= p.property_count) return false;
        const FbxProperty& v = doc_.property(p, i);
        return doc_.binary ? (v.type == 'F' || v.type == 'D') : v.type == 'n';
    };
    if (p.property_count >= 4 && !string_at(0)) {
        return error(Errc::parse_error, p, "a property entry's name is not a string");
    }
    if (p.property_count < 2) return Status::ok();
    const std::optional<std::string_view> type = fbx_string(doc_, doc_.property(p, 1));
    if (!type) return error(Errc::parse_error, p, "a property entry's type is not a string");
    const std::string_view t = *type;
    bool ok = true;
    if (t == "KString") {
        ok = string_at(4);
    } else if (t == "bool" || t == "Bool" || t == "int" || t == "Int" || t == "enum" ||
               t == "Enum" || t == "Integer") {
        ok = integer_at(4, 'I');
    } else if (t == "ULongLong") {
        ok = 4 < p.property_count && id(doc_.property(p, 4)).has_value();
    } else if (t == "KTime") {
        ok = integer_at(4, 'L');
    } else if (t == "Vector3D" || t == "ColorRGB" || t == "Vector" || t == "Color" ||
               t == "Lcl Translation" || t == "Lcl Rotation" || t == "Lcl Scaling") {
        ok = number_at(4) && number_at(5) && number_at(6);
    } else if (t == "double" || t == "Number" || t == "float" || t == "Float" ||
               t == "FieldOfView" || t == "UnitScaleFactor") {
        ok = number_at(4);
    } else if (t == "ColorAndAlpha") {
        ok = number_at(4) && number_at(5) && number_at(6) && number_at(7);
    }
    if (!ok) {
        return error(
            Errc::parse_error, p,
            "a property entry of type '" + std::string(t) + "' lacks the values of that type");
    }
    return Status::ok();
}

Status Scanner::property_entries() {
    for (const FbxNode& n : doc_.nodes) {
        if (n.name != "P" || n.parent == no_index || doc_.nodes[n.parent].name != "Properties70") {
            continue;
        }
        if (Status s = property_entry(n); !s) return s;
        // Assimp 5.2.5 copies a model's properties (its template's, where it
        // has none of its own) into its node's metadata and aborts (an
        // assertion Debian's build keeps) on the types it has no metadata for.
        const std::uint32_t owner = doc_.nodes[n.parent].parent;
        if (owner == no_index || n.property_count < 2) continue;
        const FbxNode& o = doc_.nodes[owner];
        const bool model_template =
            o.name == "PropertyTemplate" && o.parent != no_index &&
            doc_.nodes[o.parent].name == "ObjectType" && doc_.nodes[o.parent].property_count > 0 &&
            fbx_string(doc_, doc_.property(doc_.nodes[o.parent], 0)) == "Model";
        if (o.name != "Model" && !model_template) continue;
        const std::optional<std::string_view> type = fbx_string(doc_, doc_.property(n, 1));
        if (type == "KTime" || type == "ColorAndAlpha") {
            return error(Errc::unsupported, n,
                         "a model property of type '" + std::string(*type) +
                             "', on which Assimp 5.2.5 aborts");
        }
    }
    return Status::ok();
}

// An animation curve as Assimp 5.2.5 can take it: times and values as many
// and at least one, the times strictly ascending (it compares them past
// the end of an empty list), the values finite and no pair of keys so far
// apart in value, for their distance in time, that its splitting of a
// rotation into steps under 180 degrees never advances (it inserts keys
// until it does, without bound).
Status Scanner::animation_curve(const FbxNode& curve) const {
    const FbxNode* times = doc_.child(doc_.index_of(curve), "KeyTime");
    const FbxNode* values = doc_.child(doc_.index_of(curve), "KeyValueFloat");
    if (times == nullptr || values == nullptr) {
        return error(Errc::parse_error, curve,
                     "an animation curve needs KeyTime and KeyValueFloat");
    }
    std::vector<std::int64_t> t;
    std::vector<double> v;
    if (Status s = fbx_integers(doc_, *times, t); !s) return s;
    if (Status s = fbx_doubles(doc_, *values, v); !s) return s;
    if (t.empty() || t.size() != v.size()) {
        return error(Errc::parse_error, curve,
                     std::to_string(t.size()) + " key times and " + std::to_string(v.size()) +
                         " values (as many, and at least one)");
    }
    double inserted = 0.0;
    for (std::size_t k = 0; k < t.size(); ++k) {
        if (!std::isfinite(v[k])) {
            return error(Errc::numerical, *values, "value " + std::to_string(k) + " is not finite");
        }
        if (k == 0) continue;
        if (t[k] <= t[k - 1]) {
            return error(Errc::parse_error, *times,
                         "key " + std::to_string(k) + ": times must ascend strictly");
        }
        const double jump =
            std::abs(static_cast<double>(static_cast<float>(v[k]) - static_cast<float>(v[k - 1])));
        if (jump < 180.0) continue;
        const double span = static_cast<double>(t[k]) - static_cast<double>(t[k - 1]);
        inserted += jump / 179.0;
        if (span * 179.0 < 2.0 * jump || inserted > 1e6) {
            return error(Errc::unsupported, *values,
                         "key " + std::to_string(k) + ": a jump of " + std::to_string(jump) +
                             " in " + std::to_string(span) +
                             " time units, which Assimp would split into steps without end");
        }
    }
    return Status::ok();
}

Status Scanner::header() {
    // Assimp refuses a file without the header's FBXVersion, or older than
    // 7.1, after it has built part of its document (which it then loses).
    const FbxNode* header = doc_.child(no_index, "FBXHeaderExtension");
    const FbxNode* version =
        header != nullptr ? doc_.child(doc_.index_of(*header), "FBXVersion") : nullptr;
    const std::optional<std::int64_t> v =
        version != nullptr && version->property_count > 0 &&
                (doc_.binary ? doc_.property(*version, 0).type == 'I' : true)
            ? fbx_integer(doc_, doc_.property(*version, 0))
            : std::nullopt;
    if (!v) {
        const Where top = doc_.binary ? Where::byte(doc_.source, 0) : Where::line(doc_.source, 1);
        return top.parse_error("the file has no FBXHeaderExtension with an integer FBXVersion");
    }
    if (*v < 7100) {
        return error(Errc::unsupported, *version,
                     "FBXVersion " + std::to_string(*v) + " is older than 7.1, which is not read");
    }
    return Status::ok();
}

Status Scanner::objects() {
    const FbxNode* objects = doc_.child(no_index, "Objects");
    if (objects == nullptr) {
        const Where top = doc_.binary ? Where::byte(doc_.source, 0) : Where::line(doc_.source, 1);
        return top.parse_error("the file has no Objects section");
    }
    scene_.objects_node = doc_.index_of(*objects);
    for (std::uint32_t c : objects->children) {
        const FbxNode& n = doc_.nodes[c];
        if (n.property_count < 3) {
            return error(Errc::parse_error, n,
                         "an object needs an id, a name and a class (it has " +
                             std::to_string(n.property_count) + " properties)");
        }
        const std::optional<std::uint64_t> key = id(doc_.property(n, 0));
        if (!key || !fbx_string(doc_, doc_.property(n, 1)) ||
            !fbx_string(doc_, doc_.property(n, 2))) {
            return error(Errc::parse_error, n,
                         "an object's properties must be an integer id, a name and a class");
        }
        if (*key == 0) return error(Errc::parse_error, n, "an object has the root's id 0");
        // Ids name objects in connections; Assimp would take the second and
        // lose the first.
        if (!objects_.emplace(*key, c).second) {
            return error(Errc::parse_error, n, "a second object with id " + std::to_string(*key));
        }
        scene_.largest_id = std::max(scene_.largest_id, *key);
        if (n.name == "AnimationCurve") {
            if (Status s = animation_curve(n); !s) return s;
        }
    }
    return Status::ok();
}

Status Scanner::connections() {
    // Assimp needs the section, and refuses (losing what it built) a
    // connection without its type, ids or, object to property, property.
    const FbxNode* list = doc_.child(no_index, "Connections");
    if (list == nullptr) {
        const Where top = doc_.binary ? Where::byte(doc_.source, 0) : Where::line(doc_.source, 1);
        return top.parse_error("the file has no Connections section");
    }
    scene_.connections_node = doc_.index_of(*list);
    for (std::uint32_t c : list->children) {
        const FbxNode& n = doc_.nodes[c];
        if (n.name != "C") continue;
        const std::optional<std::string_view> type =
            n.property_count > 0 ? fbx_string(doc_, doc_.property(n, 0)) : std::nullopt;
        if (!type) return error(Errc::parse_error, n, "a connection needs its type first");
        if (*type == "PP") continue;
        const std::optional<std::uint64_t> source =
            n.property_count > 1 ? id(doc_.property(n, 1)) : std::nullopt;
        const std::optional<std::uint64_t> destination =
            n.property_count > 2 ? id(doc_.property(n, 2)) : std::nullopt;
        if (!source || !destination) {
            return error(Errc::parse_error, n, "a connection needs two integer object ids");
        }
        if (*type == "OP" && (n.property_count < 4 || !fbx_string(doc_, doc_.property(n, 3)))) {
            return error(Errc::parse_error, n,
                         "an object-to-property connection needs the property's name");
        }
        into_.emplace(*destination, connections_.size());
        out_of_.emplace(*source, connections_.size());
        connections_.push_back({*type, *source, *destination});
    }
    return Status::ok();
}

Status Scanner::model_hierarchy() {
    // Depth first from the root (id 0) over models connected into models.
    std::vector<std::pair<std::uint64_t, std::size_t>> stack{{0, 0}};
    while (!stack.empty()) {
        const auto [model, depth] = stack.back();
        stack.pop_back();
        const std::vector<std::uint64_t> children = sources(model, "Model", "");
        for (std::uint64_t child : children) {
            const FbxNode& n = *object(child);
            if (!scene_models_.insert(child).second) {
                return error(Errc::parse_error, n,
                             "model '" + name_of(n) + "' (id " + std::to_string(child) +
                                 ") is reached twice from the scene's root: it has two parents "
                                 "or lies on a cycle");
            }
            if (depth + 1 > fbx_max_model_depth) {
                return error(Errc::unsupported, n,
                             "the model hierarchy nests deeper than " +
                                 std::to_string(fbx_max_model_depth) + " levels");
            }
            stack.push_back({child, depth + 1});
        }
    }
    std::set<std::string> names;
    for (std::uint64_t m : scene_models_) {
        std::string name = name_of(*object(m));
        if (!names.insert(name).second) scene_.repeated_model_names.insert(std::move(name));
    }
    return Status::ok();
}

Status Scanner::matrix(const FbxNode& owner, std::string_view name, glm::dmat4& out) const {
    const FbxNode* n = doc_.child(doc_.index_of(owner), name);
    if (n == nullptr) {
        return error(Errc::parse_error, owner, "it has no " + std::string(name) + " matrix");
    }
    std::vector<double> v;
    if (Status s = fbx_doubles(doc_, *n, v); !s) return s;
    if (v.size() != 16) {
        return error(Errc::parse_error, *n,
                     "a matrix needs 16 numbers, it has " + std::to_string(v.size()));
    }
    for (int i = 0; i < 16; ++i) {
        if (!std::isfinite(v[i])) {
            return error(Errc::numerical, *n,
                         "matrix entry " + std::to_string(i) + " is not finite");
        }
        out[i / 4][i % 4] = v[i];
    }
    return Status::ok();
}

Status Scanner::indexes(const FbxNode& owner, std::string_view name, std::size_t limit,
                        std::vector<std::uint32_t>& out) const {
    out.clear();
    const FbxNode* n = doc_.child(doc_.index_of(owner), name);
    if (n == nullptr) return Status::ok();
    std::vector<std::int64_t> v;
    if (Status s = fbx_integers(doc_, *n, v); !s) return s;
    out.reserve(v.size());
    for (std::size_t i = 0; i < v.size(); ++i) {
        if (v[i] < 0 || static_cast<std::uint64_t>(v[i]) >= limit) {
            return error(Errc::out_of_range, *n,
                         "element " + std::to_string(i) + ": control point " +
                             std::to_string(v[i]) + " is out of range (the geometry has " +
                             std::to_string(limit) + ")");
        }
        out.push_back(static_cast<std::uint32_t>(v[i]));
    }
    return Status::ok();
}

Status Scanner::polygons(const FbxNode& geometry, FbxGeometry& g) {
    const FbxNode* pvi = doc_.child(doc_.index_of(geometry), "PolygonVertexIndex");
    if (pvi == nullptr) {
        return error(Errc::parse_error, geometry, "a mesh geometry needs PolygonVertexIndex");
    }
    std::vector<std::int64_t> raw;
    if (Status s = fbx_integers(doc_, *pvi, raw); !s) return s;
    const std::int64_t n = static_cast<std::int64_t>(g.control_point_count());
    g.corners.reserve(raw.size());
    g.polygon_start.assign(1, 0);
    for (std::size_t i = 0; i < raw.size(); ++i) {
        // A polygon's last corner is stored as -(index + 1); Assimp reads
        // the values as 32-bit integers.
        const std::int64_t v = raw[i];
        const std::int64_t index = v < 0 ? -(v + 1) : v;
        if (v < std::numeric_limits<std::int32_t>::min() ||
            v > std::numeric_limits<std::int32_t>::max() || index >= n) {
            return error(Errc::out_of_range, *pvi,
                         "element " + std::to_string(i) + ": control point " +
                             std::to_string(index) + " is out of range (the geometry has " +
                             std::to_string(n) + ")");
        }
        g.corners.push_back(static_cast<std::uint32_t>(index));
        if (v < 0) g.polygon_start.push_back(static_cast<std::uint32_t>(g.corners.size()));
    }
    if (g.polygon_start.back() != g.corners.size()) {
        return error(Errc::parse_error, *pvi,
                     "its last polygon is not closed (its last index is not negative)");
    }
    return Status::ok();
}

// Layer elements Assimp reads, with their data and index arrays and the
// numbers per element.
struct LayerKind {
    std::string_view element, data, index;
    std::size_t width;
};
constexpr LayerKind layer_kinds[] = {
    {"LayerElementNormal", "Normals", "NormalsIndex", 3},
    {"LayerElementBinormal", "Binormals", "BinormalsIndex", 3},
    {"LayerElementTangent", "Tangents", "TangentsIndex", 3},
    {"LayerElementUV", "UV", "UVIndex", 2},
    {"LayerElementColor", "Colors", "ColorIndex", 4},
    {"LayerElementMaterial", "Materials", "", 1},
};

Status Scanner::layer_element(const FbxNode& element, const FbxGeometry& g) {
    const LayerKind* kind = nullptr;
    for (const LayerKind& k : layer_kinds) {
        if (element.name == k.element) kind = &k;
    }
    if (kind == nullptr) return Status::ok();
    const std::uint32_t at = doc_.index_of(element);
    const auto text = [&](std::string_view name) -> std::string_view {
        const FbxNode* n = doc_.child(at, name);
        if (n == nullptr || n->property_count == 0) return {};
        return fbx_string(doc_, doc_.property(*n, 0)).value_or(std::string_view());
    };
    const std::string_view mapping = text("MappingInformationType");
    const std::string_view reference = text("ReferenceInformationType");
    std::size_t expected = 0;
    bool at_least = false;
    if (mapping == "ByPolygonVertex") {
        expected = g.corners.size();
    } else if (mapping == "ByVertice" || mapping == "ByVertex" || mapping == "ByControlPoint") {
        expected = g.control_point_count();
    } else if (mapping == "ByPolygon") {
        expected = g.polygon_count();
    } else if (mapping == "AllSame") {
        expected = 1;
        at_least = true;
    } else {
        return Status::ok();  // not read by Assimp either (ByEdge, or unknown)
    }
    const FbxNode* data = doc_.child(at, kind->data);
    const FbxNode* index = kind->index.empty() ? nullptr : doc_.child(at, kind->index);
    const bool indexed = (reference == "IndexToDirect" || reference == "Index") && index != nullptr;
    std::size_t elements = 0;
    if (data != nullptr) {
        // The data's values are not read here, only counted: an array's
        // declared count, which arrays() checked against its bytes.
        const std::size_t values = fbx_value_count(doc_, *data);
        if (values % kind->width != 0) {
            return error(Errc::parse_error, *data,
                         std::to_string(values) + " numbers, not a multiple of " +
                             std::to_string(kind->width));
        }
        elements = values / kind->width;
        if (!indexed && (at_least ? elements < expected : elements != expected)) {
            return error(Errc::parse_error, *data,
                         std::to_string(elements) + " elements for mapping " +
                             std::string(mapping) + ", which needs " + std::to_string(expected));
        }
    }
    if (!indexed) return Status::ok();
    std::vector<std::int64_t> ids;
    if (Status s = fbx_integers(doc_, *index, ids); !s) return s;
    // Assimp trims a longer ByPolygonVertex index list; a shorter one, or
    // one of another size for another mapping, it would read past.
    const bool fits = mapping == "ByPolygonVertex"
                          ? ids.size() >= expected
                          : (at_least ? ids.size() >= expected : ids.size() == expected);
    if (!fits) {
        return error(Errc::parse_error, *index,
                     std::to_string(ids.size()) + " indices for mapping " + std::string(mapping) +
                         ", which needs " + std::to_string(expected));
    }
    const std::int64_t lowest = mapping == "ByPolygonVertex" ? -1 : 0;
    for (std::size_t i = 0; i < ids.size(); ++i) {
        if (ids[i] < lowest || ids[i] >= static_cast<std::int64_t>(elements)) {
            return error(Errc::out_of_range, *index,
                         "element " + std::to_string(i) + ": index " + std::to_string(ids[i]) +
                             " is out of range (" + std::string(kind->data) + " has " +
                             std::to_string(elements) + " elements)");
        }
    }
    return Status::ok();
}

Status Scanner::layers(const FbxNode& geometry, const FbxGeometry& g) {
    for (std::uint32_t c : geometry.children) {
        if (Status s = layer_element(doc_.nodes[c], g); !s) return s;
    }
    return Status::ok();
}

Status Scanner::cluster(const FbxNode& node, const FbxGeometry& g, FbxCluster& out) {
    out.node = doc_.index_of(node);
    out.id = *id(doc_.property(node, 0));
    if (Status s = indexes(node, "Indexes", g.control_point_count(), out.indexes); !s) return s;
    if (const FbxNode* w = doc_.child(out.node, "Weights")) {
        if (Status s = fbx_doubles(doc_, *w, out.weights); !s) return s;
        for (std::size_t i = 0; i < out.weights.size(); ++i) {
            if (!std::isfinite(out.weights[i])) {
                return error(Errc::numerical, *w, "weight " + std::to_string(i) + " is not finite");
            }
        }
    }
    if (out.weights.size() != out.indexes.size()) {
        return error(Errc::parse_error, node,
                     std::to_string(out.indexes.size()) + " Indexes and " +
                         std::to_string(out.weights.size()) + " Weights");
    }
    if (Status s = matrix(node, "Transform", out.transform); !s) return s;
    if (Status s = matrix(node, "TransformLink", out.transform_link); !s) return s;
    const double det = glm::determinant(out.transform_link);
    if (!std::isfinite(det) || std::abs(det) < 1e-30) {
        return error(Errc::numerical, node,
                     "its TransformLink (the joint's bind pose) is not invertible");
    }
    const std::vector<std::uint64_t> models = sources(out.id, "Model", "");
    if (!models.empty()) {
        out.model = models.front();
        out.model_name = name_of(*object(out.model));
    }
    return Status::ok();
}

Status Scanner::skin(const FbxNode& node, FbxGeometry& g) {
    g.skin_node = doc_.index_of(node);
    const std::uint64_t own = *id(doc_.property(node, 0));
    for (std::uint64_t c : sources(own, "Deformer", "Cluster")) {
        FbxCluster cl;
        if (Status s = cluster(*object(c), g, cl); !s) return s;
        g.clusters.push_back(std::move(cl));
    }
    return Status::ok();
}

Status Scanner::blend_shape(const FbxNode& node, FbxGeometry& g) {
    const std::uint64_t own = *id(doc_.property(node, 0));
    if (g.blend_shape_node == no_index) {
        g.blend_shape_node = doc_.index_of(node);
        g.blend_shape = own;
    }
    for (std::uint64_t c : sources(own, "Deformer", "BlendShapeChannel")) {
        const FbxNode& channel = *object(c);
        FbxShapeChannel out;
        out.channel_node = doc_.index_of(channel);
        out.name = name_of(channel);
        if (const FbxNode* percent = doc_.child(out.channel_node, "DeformPercent")) {
            const std::optional<double> v = percent->property_count > 0
                                                ? fbx_number(doc_, doc_.property(*percent, 0))
                                                : std::nullopt;
            if (!v || !std::isfinite(*v)) {
                return error(Errc::numerical, *percent, "DeformPercent is not a finite number");
            }
            out.deform_percent = *v;
        }
        const std::vector<std::uint64_t> shapes = sources(c, "Geometry", "Shape");
        out.shapes = shapes.size();
        if (shapes.empty()) {
            warn(channel, "blend shape channel '" + out.name + "' has no shape; skipped");
            continue;
        }
        if (shapes.size() > 1) {
            warn(channel, "blend shape channel '" + out.name + "' has " +
                              std::to_string(shapes.size()) +
                              " shapes (in-betweens); its last, full shape is read");
        }
        for (std::uint64_t shape_id : shapes) {
            const FbxNode& shape = *object(shape_id);
            const std::uint32_t at = doc_.index_of(shape);
            if (Status s = indexes(shape, "Indexes", g.control_point_count(), out.indexes); !s) {
                return s;
            }
            std::vector<double> normals;
            for (const auto& [name, values] :
                 {std::pair<std::string_view, std::vector<double>*>{"Vertices", &out.deltas},
                  {"Normals", &normals}}) {
                const FbxNode* n = doc_.child(at, name);
                if (n == nullptr) {
                    return error(
                        Errc::parse_error, shape,
                        "a Shape needs " + std::string(name) + " (Assimp refuses one without)");
                }
                if (Status s = fbx_doubles(doc_, *n, *values); !s) return s;
                if (values->size() != 3 * out.indexes.size()) {
                    return error(Errc::parse_error, *n,
                                 std::to_string(values->size()) + " numbers for " +
                                     std::to_string(out.indexes.size()) + " indexes (3 each)");
                }
            }
            for (std::size_t i = 0; i < out.deltas.size(); ++i) {
                if (!std::isfinite(out.deltas[i])) {
                    return error(Errc::numerical, shape,
                                 "Vertices value " + std::to_string(i) + " is not finite");
                }
            }
            for (std::size_t i = 1; i < out.indexes.size(); ++i) {
                if (out.indexes[i] <= out.indexes[i - 1]) {
                    return error(Errc::parse_error, shape,
                                 "its Indexes are not ascending at element " + std::to_string(i));
                }
            }
            out.shape_node = at;
        }
        g.channels.push_back(std::move(out));
    }
    return Status::ok();
}

Status Scanner::geometry(const FbxNode& node, FbxGeometry& g) {
    g.node = doc_.index_of(node);
    g.id = *id(doc_.property(node, 0));
    g.name = name_of(node);
    const FbxNode* vertices = doc_.child(g.node, "Vertices");
    if (vertices == nullptr)
        return error(Errc::parse_error, node, "a mesh geometry needs Vertices");
    g.vertices_node = doc_.index_of(*vertices);
    if (Status s = fbx_doubles(doc_, *vertices, g.control_points); !s) return s;
    if (g.control_points.size() % 3 != 0) {
        return error(Errc::parse_error, *vertices,
                     std::to_string(g.control_points.size()) + " numbers, not a multiple of 3");
    }
    if (g.control_point_count() >= std::numeric_limits<std::int32_t>::max()) {
        return error(Errc::out_of_range, *vertices,
                     "more control points than 32-bit indices address");
    }
    for (std::size_t i = 0; i < g.control_points.size(); ++i) {
        if (!std::isfinite(g.control_points[i])) {
            return error(Errc::parse_error, *vertices,
                         "control point " + std::to_string(i / 3) + ": " +
                             static_cast<char>('x' + i % 3) + " is not a finite number");
        }
    }
    if (Status s = polygons(node, g); !s) return s;
    if (Status s = layers(node, g); !s) return s;
    for (std::uint64_t d : sources(g.id, "Deformer", "")) {
        const FbxNode& deformer = *object(d);
        if (class_of(deformer) == "Skin") {
            if (g.skin_node != no_index) {
                warn(deformer, "a second skin on geometry '" + g.name + "'; the first is read");
                continue;
            }
            if (Status s = skin(deformer, g); !s) return s;
        } else if (class_of(deformer) == "BlendShape") {
            if (Status s = blend_shape(deformer, g); !s) return s;
        }
    }
    return Status::ok();
}

Status Scanner::run() {
    if (Status s = arrays(); !s) return s;
    if (Status s = header(); !s) return s;
    if (Status s = property_entries(); !s) return s;
    if (Status s = settings(); !s) return s;
    if (Status s = objects(); !s) return s;
    if (Status s = connections(); !s) return s;
    if (Status s = model_hierarchy(); !s) return s;
    if (const FbxNode* d = doc_.child(no_index, "Definitions")) {
        scene_.definitions_node = doc_.index_of(*d);
    }
    for (std::uint32_t c : doc_.nodes[scene_.objects_node].children) {
        const FbxNode& n = doc_.nodes[c];
        if (n.name != "Geometry" || class_of(n) != "Mesh") continue;
        const std::uint64_t own = *id(doc_.property(n, 0));
        std::uint64_t model = 0;
        for (std::uint64_t m : destinations(own, "Model")) {
            if (scene_models_.count(m) != 0) {
                model = m;
                break;
            }
        }
        if (model == 0) continue;  // not in the scene
        FbxGeometry g;
        if (Status s = geometry(n, g); !s) return s;
        g.model = model;
        g.model_node = objects_.at(model);
        g.model_name = name_of(doc_.nodes[g.model_node]);
        scene_.geometries.push_back(std::move(g));
    }
    return Status::ok();
}

}  // namespace

Status scan_fbx(const FbxDocument& doc, FbxScene& scene, LoadReport& report) {
    scene = FbxScene{};
    Status s = Scanner(doc, scene, report).run();
    if (!s) scene = FbxScene{};
    return s;
}

}  // namespace dfm::mesh
