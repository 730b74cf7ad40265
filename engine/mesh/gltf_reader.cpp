// The one translation unit that compiles tinygltf's implementation.
#define TINYGLTF_IMPLEMENTATION
#include "mesh/gltf_model.hpp"

#include <cmath>
#include <cstring>
#include <fstream>
#include <map>
#include <new>
#include <stdexcept>

#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>

#include "mesh/gltf_accessors.hpp"
#include "mesh/gltf_io.hpp"
#include "mesh/gltf_skin_reader.hpp"

namespace dfm::mesh {

void split_gltf_spec(std::string_view spec, std::string& file, std::string& selector) {
    const std::size_t hash = spec.rfind("#mesh=");
    if (hash == std::string_view::npos) {
        file = std::string(spec);
        selector.clear();
        return;
    }
    file = std::string(spec.substr(0, hash));
    selector = std::string(spec.substr(hash + 6));
}

namespace {

// True when `p` is `root` or lies below it; both absolute and lexically
// normal. A folder's trailing separator leaves an empty last element.
bool inside(const std::filesystem::path& p, const std::filesystem::path& root) {
    auto at = p.begin();
    for (const std::filesystem::path& part : root) {
        if (part.empty()) break;
        if (at == p.end() || *at != part) return false;
        ++at;
    }
    return true;
}

// A URI's scheme, RFC 3986: a letter, then letters, digits, '+', '-' or '.',
// then ':'.
bool has_scheme(std::string_view uri) {
    const std::size_t colon = uri.find(':');
    if (colon == std::string_view::npos || colon == 0) return false;
    const auto letter = [](char c) { return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z'); };
    if (!letter(uri[0])) return false;
    for (std::size_t i = 1; i < colon; ++i) {
        const char c = uri[i];
        if (!letter(c) && !(c >= '0' && c <= '9') && c != '+' && c != '-' && c != '.') return false;
    }
    return true;
}

// External buffers are read only where ExternalFiles allows, through these
// callbacks and not through tinygltf's defaults (which expand paths with
// wordexp and also look in the process's working folder). tinygltf hands
// them the URI, %-decoded, joined onto the document's folder: the URI is
// what follows that folder's prefix.
class FileAccess {
public:
    explicit FileAccess(const ExternalFiles* files) : files_(files) {
        if (files_ == nullptr) return;
        prefix_ = files_->folder.string();
        if (prefix_.empty() || prefix_.back() != '/') prefix_ += '/';
        std::error_code ec;
        folder_ = std::filesystem::absolute(files_->folder, ec).lexically_normal();
        if (!files_->wider_folder.empty())
            wider_ = std::filesystem::absolute(files_->wider_folder, ec).lexically_normal();
    }

    // Whether `path` (as tinygltf made it) may be read. A refused URI is
    // remembered, the first one, for the load's message.
    bool allowed(const std::string& path) {
        if (files_ == nullptr || !path.starts_with(prefix_)) return false;
        const std::string uri = path.substr(prefix_.size());
        std::string why;
        if (has_scheme(uri)) {
            why = "a URI with a scheme is not followed";
        } else if (uri.starts_with('/') || uri.starts_with('\\')) {
            why = "an absolute path is not followed";
        } else {
            const std::filesystem::path target = (folder_ / uri).lexically_normal();
            if (inside(target, folder_) || (!wider_.empty() && inside(target, wider_))) return true;
            why = wider_.empty() ? "it leads out of the asset's folder"
                                 : "it leads out of the asset's folder and of " + wider_.string();
        }
        if (refused_.empty()) {
            refused_ = "external file URI '" + uri + "' refused: " + why +
                       " (a glTF document's external files are read only inside its own "
                       "folder, or a folder the host names)";
        }
        return false;
    }

    // The first refusal, or "".
    const std::string& refused() const { return refused_; }

private:
    const ExternalFiles* files_;
    std::string prefix_;
    std::filesystem::path folder_;
    std::filesystem::path wider_;
    std::string refused_;
};

bool file_exists(const std::string& path, void* user) {
    auto* access = static_cast<FileAccess*>(user);
    std::error_code ec;
    return access->allowed(path) && std::filesystem::is_regular_file(path, ec);
}

std::string expand_path(const std::string& path, void*) {
    return path;
}

bool read_whole_file(std::vector<unsigned char>* out, std::string* err, const std::string& path,
                     void* user) {
    auto* access = static_cast<FileAccess*>(user);
    if (!access->allowed(path)) {
        if (err) *err += "external file '" + path + "' refused\n";
        return false;
    }
    std::ifstream in(path, std::ios::binary);
    if (!in) {
        if (err) *err += "cannot open external file '" + path + "'\n";
        return false;
    }
    out->assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    return true;
}

bool refuse_write(std::string* err, const std::string&, const std::vector<unsigned char>&, void*) {
    if (err) *err += "writing is not done through tinygltf\n";
    return false;
}

// Images are kept as the document's bytes; nothing decodes them.
bool keep_image(tinygltf::Image*, const int, std::string*, std::string*, int, int,
                const unsigned char*, int, void*) {
    return true;
}

std::string one_line(std::string text) {
    while (!text.empty() && (text.back() == '\n' || text.back() == '\r')) text.pop_back();
    for (char& c : text) {
        if (c == '\n' || c == '\r') c = ' ';
    }
    return text;
}

glm::dmat4 local_matrix(const tinygltf::Node& node) {
    if (node.matrix.size() == 16) return glm::make_mat4(node.matrix.data());
    glm::dmat4 m(1.0);
    if (node.translation.size() == 3) {
        m = glm::translate(
            m, glm::dvec3(node.translation[0], node.translation[1], node.translation[2]));
    }
    if (node.rotation.size() == 4) {
        m *= glm::mat4_cast(
            glm::dquat(node.rotation[3], node.rotation[0], node.rotation[1], node.rotation[2]));
    }
    if (node.scale.size() == 3) {
        m = glm::scale(m, glm::dvec3(node.scale[0], node.scale[1], node.scale[2]));
    }
    return m;
}

struct Instance {
    int mesh;
    glm::dmat4 world;
    int node = -1;
    int skin = -1;
};

class Reader {
public:
    Reader(const tinygltf::Model& model, std::string_view source, Mesh& host, GltfAsset& asset,
           LoadReport& report)
        : model_(model), source_(source), host_(host), asset_(asset), report_(report) {}

    Status instances(const std::string& selector, std::vector<Instance>& out);
    Status add_mesh(const Instance& instance);
    void finish_slots();

private:
    Status add_primitive(const Instance& instance, int p);
    Status add_range(const Instance& instance, const tinygltf::Primitive& prim,
                     const std::string& where, int position, std::uint32_t& range);
    Status error(Errc code, const std::string& what) const {
        return Status(code, std::string(source_) + ": " + what);
    }
    void warn(const std::string& what) { report_.warn(std::string(source_) + ": " + what); }

    const tinygltf::Model& model_;
    std::string_view source_;
    Mesh& host_;
    GltfAsset& asset_;
    LoadReport& report_;
    std::map<int, std::uint32_t> range_of_position_;
};

Status Reader::instances(const std::string& selector, std::vector<Instance>& out) {
    const int meshes = static_cast<int>(model_.meshes.size());
    if (!selector.empty()) {
        for (int m = 0; m < meshes; ++m) {
            if (model_.meshes[m].name == selector) {
                out.push_back({m, glm::dmat4(1.0)});
                return Status::ok();
            }
        }
        const bool digits = selector.find_first_not_of("0123456789") == std::string::npos;
        if (digits && selector.size() < 10 && std::stoi(selector) < meshes) {
            out.push_back({std::stoi(selector), glm::dmat4(1.0)});
            return Status::ok();
        }
        std::string names;
        for (int m = 0; m < meshes && m < 20; ++m) {
            names += (m ? ", '" : "'") + model_.meshes[m].name + "'";
        }
        return error(Errc::not_found, "no mesh named or numbered '" + selector +
                                          "' (the file has " + std::to_string(meshes) + " meshes" +
                                          (names.empty() ? "" : ": " + names) + ")");
    }
    if (model_.scenes.empty()) {
        for (int m = 0; m < meshes; ++m) out.push_back({m, glm::dmat4(1.0)});
        return Status::ok();
    }
    const int scene = model_.defaultScene >= 0 ? model_.defaultScene : 0;
    if (scene >= static_cast<int>(model_.scenes.size())) {
        return error(Errc::out_of_range, "the default scene " + std::to_string(scene) +
                                             " does not exist (the file has " +
                                             std::to_string(model_.scenes.size()) + ")");
    }
    const int nodes = static_cast<int>(model_.nodes.size());
    std::vector<bool> seen(model_.nodes.size(), false);
    std::vector<bool> mesh_taken(model_.meshes.size(), false);
    std::vector<std::pair<int, glm::dmat4>> stack;
    const std::vector<int>& roots = model_.scenes[scene].nodes;
    for (auto it = roots.rbegin(); it != roots.rend(); ++it)
        stack.push_back({*it, glm::dmat4(1.0)});
    while (!stack.empty()) {
        const auto [n, parent] = stack.back();
        stack.pop_back();
        if (n < 0 || n >= nodes) {
            return error(Errc::out_of_range,
                         "scene " + std::to_string(scene) + ": node " + std::to_string(n) +
                             " does not exist (the file has " + std::to_string(nodes) + ")");
        }
        if (seen[n]) {
            return error(Errc::parse_error,
                         "node " + std::to_string(n) +
                             " is reached twice: the node hierarchy must be a tree");
        }
        seen[n] = true;
        const tinygltf::Node& node = model_.nodes[n];
        const glm::dmat4 world = parent * local_matrix(node);
        if (node.mesh >= meshes) {
            return error(Errc::out_of_range,
                         "node " + std::to_string(n) + ": mesh " + std::to_string(node.mesh) +
                             " does not exist (the file has " + std::to_string(meshes) + ")");
        }
        if (node.mesh >= 0) {
            if (mesh_taken[node.mesh]) {
                warn("node " + std::to_string(n) + " instances mesh " + std::to_string(node.mesh) +
                     " again" +
                     (node.skin >= 0 ? " with skin " + std::to_string(node.skin) : std::string()) +
                     "; only its first instance is loaded");
            } else {
                mesh_taken[node.mesh] = true;
                // A skinned mesh lives in its skeleton's space, not its node's.
                out.push_back({node.mesh, node.skin >= 0 ? glm::dmat4(1.0) : world, n, node.skin});
            }
        }
        for (auto it = node.children.rbegin(); it != node.children.rend(); ++it) {
            stack.push_back({*it, world});
        }
    }
    return Status::ok();
}

Status Reader::add_mesh(const Instance& instance) {
    const tinygltf::Mesh& mesh = model_.meshes[instance.mesh];
    for (int p = 0; p < static_cast<int>(mesh.primitives.size()); ++p) {
        if (Status s = add_primitive(instance, p); !s) return s;
    }
    return Status::ok();
}

Status Reader::add_range(const Instance& instance, const tinygltf::Primitive& prim,
                         const std::string& where, int position, std::uint32_t& range) {
    if (const auto it = range_of_position_.find(position); it != range_of_position_.end()) {
        range = it->second;
        return Status::ok();
    }
    if (Status s = check_accessor_shape(model_, position, TINYGLTF_TYPE_VEC3, where + " POSITION");
        !s) {
        return error(s.code(), s.message());
    }
    if (model_.accessors[position].componentType != TINYGLTF_COMPONENT_TYPE_FLOAT) {
        const bool quantized = std::find(model_.extensionsUsed.begin(), model_.extensionsUsed.end(),
                                         "KHR_mesh_quantization") != model_.extensionsUsed.end();
        return error(Errc::unsupported,
                     where + " POSITION (accessor " + std::to_string(position) +
                         "): component type " +
                         std::to_string(model_.accessors[position].componentType) +
                         (quantized ? " (quantized, KHR_mesh_quantization) is not supported"
                                    : " is not float, as glTF requires without extensions"));
    }
    std::vector<double> xyz;
    if (Status s = read_accessor(model_, position, 3, where + " POSITION", xyz); !s) {
        return error(s.code(), s.message());
    }
    const std::size_t count = xyz.size() / 3;
    if (host_.positions.size() + count >= no_index) {
        return error(Errc::out_of_range, where + ": more vertices than 32-bit indices address");
    }
    GltfVertexRange r;
    r.mesh = instance.mesh;
    r.node = instance.node;
    r.skin = instance.skin;
    r.first_vertex = static_cast<std::uint32_t>(host_.positions.size());
    r.count = static_cast<std::uint32_t>(count);
    r.world = instance.world;
    r.position.accessor = position;
    std::vector<double> normals, tangents;
    if (const auto it = prim.attributes.find("NORMAL"); it != prim.attributes.end()) {
        if (Status s = read_accessor(model_, it->second, 3, where + " NORMAL", normals); !s) {
            return error(s.code(), s.message());
        }
        if (normals.size() != xyz.size()) {
            return error(Errc::parse_error, where + " NORMAL (accessor " +
                                                std::to_string(it->second) + ") has " +
                                                std::to_string(normals.size() / 3) +
                                                " elements, POSITION " + std::to_string(count));
        }
        r.normal.accessor = it->second;
    }
    if (const auto it = prim.attributes.find("TANGENT"); it != prim.attributes.end()) {
        if (Status s = read_accessor(model_, it->second, 4, where + " TANGENT", tangents); !s) {
            return error(s.code(), s.message());
        }
        if (tangents.size() / 4 != count) {
            return error(Errc::parse_error, where + " TANGENT (accessor " +
                                                std::to_string(it->second) + ") has " +
                                                std::to_string(tangents.size() / 4) +
                                                " elements, POSITION " + std::to_string(count));
        }
        r.tangent.accessor = it->second;
    }
    for (std::size_t v = 0; v < count; ++v) {
        const glm::dvec3 local(xyz[3 * v], xyz[3 * v + 1], xyz[3 * v + 2]);
        const glm::dvec3 world = glm::dvec3(instance.world * glm::dvec4(local, 1.0));
        if (!std::isfinite(world.x) || !std::isfinite(world.y) || !std::isfinite(world.z)) {
            return error(Errc::parse_error, where + " POSITION (accessor " +
                                                std::to_string(position) + ") element " +
                                                std::to_string(v) + " is not finite");
        }
        host_.positions.push_back(world);
        asset_.local_positions.push_back(local);
        asset_.normals.push_back(
            normals.empty() ? glm::dvec3(0.0)
                            : glm::dvec3(normals[3 * v], normals[3 * v + 1], normals[3 * v + 2]));
        asset_.tangents.push_back(tangents.empty()
                                      ? glm::dvec4(0.0)
                                      : glm::dvec4(tangents[4 * v], tangents[4 * v + 1],
                                                   tangents[4 * v + 2], tangents[4 * v + 3]));
    }
    range = static_cast<std::uint32_t>(asset_.ranges.size());
    asset_.ranges.push_back(r);
    range_of_position_[position] = range;
    return Status::ok();
}

Status Reader::add_primitive(const Instance& instance, int p) {
    const tinygltf::Primitive& prim = model_.meshes[instance.mesh].primitives[p];
    const std::string where =
        "mesh " + std::to_string(instance.mesh) + " primitive " + std::to_string(p);
    const int mode = prim.mode < 0 ? TINYGLTF_MODE_TRIANGLES : prim.mode;
    if (prim.extensions.count("KHR_draco_mesh_compression") != 0) {
        return error(Errc::unsupported,
                     where + ": Draco compression (KHR_draco_mesh_compression) is not supported");
    }
    if (mode < TINYGLTF_MODE_TRIANGLES) {
        warn(where + ": mode " + std::to_string(mode) +
             " (points or lines) is not a surface; skipped");
        return Status::ok();
    }
    if (mode > TINYGLTF_MODE_TRIANGLE_FAN) {
        return error(Errc::parse_error, where + ": unknown mode " + std::to_string(mode));
    }
    const auto position = prim.attributes.find("POSITION");
    if (position == prim.attributes.end()) {
        return error(Errc::parse_error, where + " has no POSITION attribute");
    }
    std::uint32_t range = 0;
    if (Status s = add_range(instance, prim, where, position->second, range); !s) return s;
    const GltfVertexRange& r = asset_.ranges[range];
    std::vector<double> corners;
    if (prim.indices >= 0) {
        if (Status s = check_accessor_shape(model_, prim.indices, TINYGLTF_TYPE_SCALAR,
                                            where + " indices");
            !s) {
            return error(s.code(), s.message());
        }
        const int type = model_.accessors[prim.indices].componentType;
        if (type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE &&
            type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
            type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT) {
            return error(Errc::parse_error, where + " indices (accessor " +
                                                std::to_string(prim.indices) +
                                                "): component type " + std::to_string(type) +
                                                " is not an unsigned integer");
        }
        if (Status s = read_accessor(model_, prim.indices, 1, where + " indices", corners); !s) {
            return error(s.code(), s.message());
        }
        for (std::size_t i = 0; i < corners.size(); ++i) {
            if (corners[i] >= r.count) {
                return error(Errc::out_of_range,
                             where + " indices (accessor " + std::to_string(prim.indices) +
                                 ") element " + std::to_string(i) + ": vertex " +
                                 std::to_string(static_cast<std::uint64_t>(corners[i])) +
                                 " is out of range (POSITION has " + std::to_string(r.count) +
                                 " vertices)");
            }
        }
    } else {
        corners.resize(r.count);
        for (std::uint32_t v = 0; v < r.count; ++v) corners[v] = v;
    }
    GltfPrimitive record;
    record.mesh = instance.mesh;
    record.primitive = p;
    record.range = range;
    record.first_triangle = static_cast<std::uint32_t>(host_.triangles.size());
    const auto corner = [&](std::size_t i) {
        return r.first_vertex + static_cast<std::uint32_t>(corners[i]);
    };
    std::size_t dropped = 0;
    const auto add = [&](std::uint32_t a, std::uint32_t b, std::uint32_t c) {
        ++report_.polygons;
        if (a == b || b == c || a == c) {
            ++dropped;
            return;
        }
        host_.triangles.push_back({a, b, c});
    };
    const std::size_t n = corners.size();
    if (mode == TINYGLTF_MODE_TRIANGLES) {
        if (n % 3 != 0) {
            warn(where + ": " + std::to_string(n) + " indices, not a multiple of 3; the last " +
                 std::to_string(n % 3) + " ignored");
        }
        for (std::size_t i = 0; i + 2 < n; i += 3) add(corner(i), corner(i + 1), corner(i + 2));
    } else if (mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
        for (std::size_t i = 0; i + 2 < n; ++i) {
            if (i % 2 == 0) {
                add(corner(i), corner(i + 1), corner(i + 2));
            } else {
                add(corner(i + 1), corner(i), corner(i + 2));
            }
        }
    } else {
        for (std::size_t i = 1; i + 1 < n; ++i) add(corner(0), corner(i), corner(i + 1));
    }
    if (dropped > 0) {
        report_.dropped_faces += dropped;
        warn(where + ": " + std::to_string(dropped) +
             (dropped == 1 ? " triangle repeats a vertex; dropped"
                           : " triangles repeat a vertex; dropped"));
    }
    record.triangle_count =
        static_cast<std::uint32_t>(host_.triangles.size() - record.first_triangle);
    asset_.primitives.push_back(record);
    return Status::ok();
}

void Reader::finish_slots() {
    std::vector<bool> rewritten(model_.accessors.size(), false);
    for (const GltfVertexRange& r : asset_.ranges) {
        for (int a : {r.position.accessor, r.normal.accessor, r.tangent.accessor}) {
            if (a >= 0) rewritten[a] = true;
        }
    }
    const std::vector<std::vector<bool>> claimed = claimed_bytes(model_, rewritten);
    for (GltfVertexRange& r : asset_.ranges) {
        r.position = slot_of(model_, r.position.accessor, claimed);
        if (r.normal.accessor >= 0) r.normal = slot_of(model_, r.normal.accessor, claimed);
        if (r.tangent.accessor >= 0) r.tangent = slot_of(model_, r.tangent.accessor, claimed);
    }
}

// The JSON chunk of a GLB (tinygltf has checked the header), or the whole
// text of a .gltf.
std::string json_text(std::string_view bytes, bool binary) {
    if (!binary) return std::string(bytes);
    std::uint32_t length = 0;
    std::memcpy(&length, bytes.data() + 12, sizeof length);
    return std::string(bytes.substr(20, length));
}

}  // namespace

Status read_gltf(std::string_view bytes, std::string_view source, const ExternalFiles* files,
                 const std::string& selector, Mesh& host, GltfAsset& asset, Skin& skin,
                 LoadReport& report) {
    host = Mesh{};
    asset = GltfAsset{};
    skin = Skin{};
    const std::string name(source);
    if (bytes.size() > 0xFFFFFFFFu) {
        return Status(Errc::out_of_range, name + ": more than 4 GiB, larger than glTF allows");
    }
    tinygltf::TinyGLTF loader;
    FileAccess access(files);
    tinygltf::FsCallbacks fs{&file_exists, &expand_path, &read_whole_file, &refuse_write, &access};
    loader.SetFsCallbacks(fs);
    loader.SetImageLoader(&keep_image, nullptr);
    tinygltf::Model model;
    std::string err, warn;
    const bool binary = bytes.size() >= 4 && bytes.substr(0, 4) == "glTF";
    const std::string dir = files != nullptr ? files->folder.string() : std::string();
    const auto* data = reinterpret_cast<const unsigned char*>(bytes.data());
    bool ok = false;
    // tinygltf parses without exceptions, but its JSON library may still
    // throw on a value of the wrong type; that is the file's fault.
    try {
        ok = binary ? loader.LoadBinaryFromMemory(&model, &err, &warn, data,
                                                  static_cast<unsigned int>(bytes.size()), dir)
                    : loader.LoadASCIIFromString(&model, &err, &warn, bytes.data(),
                                                 static_cast<unsigned int>(bytes.size()), dir);
    } catch (const std::bad_alloc&) {
        throw;
    } catch (const std::exception& e) {
        err = e.what();
        ok = false;
    }
    if (!ok && !access.refused().empty()) {
        return Status(Errc::unsupported, name + ": " + access.refused());
    }
    if (!ok) {
        return Status(Errc::parse_error, name + ": not a valid glTF 2.0 " +
                                             (binary ? "GLB" : "document") + ": " +
                                             one_line(err.empty() ? warn : err));
    }
    if (!warn.empty()) report.warn(name + ": " + one_line(warn));
    // What tinygltf skipped and still loaded (an animation channel that
    // names no node, for one) it reports as an error text.
    if (!err.empty()) report.warn(name + ": skipped: " + one_line(err));
    for (const std::string& ext : model.extensionsRequired) {
        if (ext == "KHR_draco_mesh_compression" || ext == "EXT_meshopt_compression" ||
            ext == "KHR_mesh_quantization") {
            return Status(Errc::unsupported,
                          name + ": the file requires " + ext + ", which is not supported");
        }
    }
    Reader reader(model, source, host, asset, report);
    std::vector<Instance> instances;
    if (Status s = reader.instances(selector, instances); !s) return s;
    for (const Instance& instance : instances) {
        if (Status s = reader.add_mesh(instance); !s) {
            host = Mesh{};
            asset = GltfAsset{};
            return s;
        }
    }
    if (host.triangles.empty()) {
        host = Mesh{};
        asset = GltfAsset{};
        return Status(Errc::parse_error,
                      name + ": no triangle primitive in " +
                          (selector.empty() ? "the default scene" : "mesh '" + selector + "'"));
    }
    if (Status s = read_gltf_skin(model, source, asset, skin, report); !s) {
        host = Mesh{};
        asset = GltfAsset{};
        return s;
    }
    reader.finish_slots();
    asset.source = name;
    asset.json = json_text(bytes, binary);
    asset.buffers.reserve(model.buffers.size());
    for (const tinygltf::Buffer& b : model.buffers) {
        asset.buffers.emplace_back(b.data.begin(), b.data.end());
    }
    return Status::ok();
}

}  // namespace dfm::mesh
