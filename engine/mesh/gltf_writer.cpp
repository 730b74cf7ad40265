#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

#include <glm/mat3x3.hpp>
#include <glm/matrix.hpp>
#include <nlohmann/json.hpp>

#include "mesh/gltf_edit.hpp"
#include "mesh/gltf_io.hpp"

namespace dfm::mesh {

namespace {

using nlohmann::json;

constexpr int float_type = 5126;

std::string base64(std::string_view bytes) {
    static constexpr char digits[] =
        "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    out.reserve((bytes.size() + 2) / 3 * 4);
    for (std::size_t i = 0; i < bytes.size(); i += 3) {
        const std::uint32_t b0 = static_cast<unsigned char>(bytes[i]);
        const std::uint32_t b1 =
            i + 1 < bytes.size() ? static_cast<unsigned char>(bytes[i + 1]) : 0;
        const std::uint32_t b2 =
            i + 2 < bytes.size() ? static_cast<unsigned char>(bytes[i + 2]) : 0;
        const std::uint32_t triple = (b0 << 16) | (b1 << 8) | b2;
        out += digits[(triple >> 18) & 63];
        out += digits[(triple >> 12) & 63];
        out += i + 1 < bytes.size() ? digits[(triple >> 6) & 63] : '=';
        out += i + 2 < bytes.size() ? digits[triple & 63] : '=';
    }
    return out;
}

void put_u32(std::string& out, std::uint32_t v) {
    char b[4];
    std::memcpy(b, &v, 4);
    out.append(b, 4);
}

// The document and its buffers as they are being written: new data goes to
// the end of buffer 0 as new buffer views.
struct Document {
    json doc;
    std::vector<std::string> buffers;

    int append_view(const std::vector<float>& values) {
        std::string& b = buffers[0];
        while (b.size() % 4 != 0) b.push_back('\0');
        const std::size_t offset = b.size();
        b.append(reinterpret_cast<const char*>(values.data()), values.size() * sizeof(float));
        json view = {{"buffer", 0}, {"byteOffset", offset}, {"byteLength", values.size() * 4}};
        doc["bufferViews"].push_back(view);
        return static_cast<int>(doc["bufferViews"].size()) - 1;
    }

    // A new dense float accessor over `values`; POSITION accessors carry bounds.
    int append_accessor(const std::vector<float>& values, int components, bool bounds) {
        const int view = append_view(values);
        json a = {{"bufferView", view},
                  {"componentType", float_type},
                  {"count", values.size() / components},
                  {"type", components == 1   ? "SCALAR"
                           : components == 3 ? "VEC3"
                                             : "VEC4"}};
        if (bounds) set_bounds(a, values, components);
        doc["accessors"].push_back(a);
        return static_cast<int>(doc["accessors"].size()) - 1;
    }

    static void set_bounds(json& accessor, const std::vector<float>& values, int components) {
        std::vector<double> lo(components, std::numeric_limits<double>::infinity());
        std::vector<double> hi(components, -std::numeric_limits<double>::infinity());
        for (std::size_t i = 0; i < values.size(); ++i) {
            lo[i % components] = std::min<double>(lo[i % components], values[i]);
            hi[i % components] = std::max<double>(hi[i % components], values[i]);
        }
        if (values.empty()) lo = hi = std::vector<double>(components, 0.0);
        accessor["min"] = lo;
        accessor["max"] = hi;
    }

    // Writes `values` (every element of the accessor) where `slot` says, or
    // into a new buffer view that the accessor then reads densely.
    void write(const GltfSlot& slot, const std::vector<float>& values, int components,
               const std::vector<bool>& changed) {
        json& a = doc["accessors"][slot.accessor];
        if (slot.in_place) {
            std::string& b = buffers[slot.buffer];
            for (std::size_t e = 0; e < changed.size(); ++e) {
                if (!changed[e]) continue;
                std::memcpy(b.data() + slot.offset + e * slot.stride, &values[e * components],
                            components * sizeof(float));
            }
            return;
        }
        a["bufferView"] = append_view(values);
        a["byteOffset"] = 0;
        a["componentType"] = float_type;
        a.erase("sparse");
        a.erase("normalized");
    }
};

glm::dvec3 normalized_or(const glm::dvec3& v, const glm::dvec3& fallback) {
    const double len = glm::length(v);
    return len > 0.0 && std::isfinite(len) ? v / len : fallback;
}

std::string finish(Document& d, bool binary) {
    std::string out;
    json& buffers = d.doc["buffers"];
    for (std::size_t b = 0; b < d.buffers.size(); ++b) {
        buffers[b]["byteLength"] = d.buffers[b].size();
        if (binary && b == 0) {
            buffers[b].erase("uri");
        } else {
            buffers[b]["uri"] = "data:application/octet-stream;base64," + base64(d.buffers[b]);
        }
    }
    // Names come from file names, which need not be UTF-8.
    std::string text = d.doc.dump(-1, ' ', false, json::error_handler_t::replace);
    if (!binary) return text;
    while (text.size() % 4 != 0) text.push_back(' ');
    std::string bin = d.buffers.empty() ? std::string() : d.buffers[0];
    while (bin.size() % 4 != 0) bin.push_back('\0');
    const std::size_t total = 12 + 8 + text.size() + (bin.empty() ? 0 : 8 + bin.size());
    out.reserve(total);
    out += "glTF";
    put_u32(out, 2);
    put_u32(out, static_cast<std::uint32_t>(total));
    put_u32(out, static_cast<std::uint32_t>(text.size()));
    put_u32(out, 0x4E4F534Au);
    out += text;
    if (!bin.empty()) {
        put_u32(out, static_cast<std::uint32_t>(bin.size()));
        put_u32(out, 0x004E4942u);
        out += bin;
    }
    return out;
}

}  // namespace

Status write_gltf(const GltfAsset& asset, std::span<const glm::dvec3> host_positions,
                  std::span<const Triangle> host_triangles, const std::string& morph_target,
                  const std::string& morph_target_extras, bool binary, std::string& out) {
    const std::size_t n = asset.local_positions.size();
    if (host_positions.size() != n) {
        return Status(Errc::internal, asset.source + ": the mesh has " +
                                          std::to_string(host_positions.size()) +
                                          " vertices, the asset it came from " + std::to_string(n));
    }
    Document d;
    d.doc = json::parse(asset.json, nullptr, false);
    if (d.doc.is_discarded() || !d.doc.is_object()) {
        return Status(Errc::internal, asset.source + ": the loaded document no longer parses");
    }
    d.buffers = asset.buffers;
    if (d.buffers.empty()) {
        return Status(Errc::internal, asset.source + ": the loaded asset has no buffer");
    }

    EditedVertices edit = edited_vertices(asset, host_positions, host_triangles);
    if (!morph_target.empty()) {
        add_morph_target(asset, edit, morph_target, morph_target_extras, d.doc,
                         [&](const std::vector<float>& v, int components, bool bounds) {
                             return d.append_accessor(v, components, bounds);
                         });
        out = finish(d, binary);
        return Status::ok();
    }
    for (const GltfVertexRange& r : asset.ranges) {
        const std::vector<bool> moved(edit.moved.begin() + r.first_vertex,
                                      edit.moved.begin() + r.first_vertex + r.count);
        const std::vector<bool> dirty(edit.dirty.begin() + r.first_vertex,
                                      edit.dirty.begin() + r.first_vertex + r.count);
        if (std::find(dirty.begin(), dirty.end(), true) == dirty.end()) continue;
        std::vector<float> xyz(3 * r.count), nrm(3 * r.count), tan(4 * r.count);
        for (std::uint32_t i = 0; i < r.count; ++i) {
            const std::size_t v = r.first_vertex + i;
            for (int c = 0; c < 3; ++c) {
                xyz[3 * i + c] = static_cast<float>(edit.local_positions[v][c]);
                nrm[3 * i + c] = static_cast<float>(edit.normals[v][c]);
            }
            for (int c = 0; c < 4; ++c) tan[4 * i + c] = static_cast<float>(edit.tangents[v][c]);
        }
        d.write(r.position, xyz, 3, moved);
        Document::set_bounds(d.doc["accessors"][r.position.accessor], xyz, 3);
        if (r.normal.accessor >= 0) d.write(r.normal, nrm, 3, dirty);
        if (r.tangent.accessor >= 0) d.write(r.tangent, tan, 4, dirty);
    }
    out = finish(d, binary);
    return Status::ok();
}

void write_fresh_gltf(std::span<const glm::dvec3> positions, std::span<const Triangle> triangles,
                      const std::string& name, bool binary, std::string& out) {
    std::vector<glm::dvec3> normals(positions.size(), glm::dvec3(0.0));
    for (const Triangle& t : triangles) {
        const glm::dvec3 f =
            glm::cross(positions[t[1]] - positions[t[0]], positions[t[2]] - positions[t[0]]);
        for (std::uint32_t v : t) normals[v] += f;
    }
    std::vector<float> xyz, nrm;
    xyz.reserve(3 * positions.size());
    nrm.reserve(3 * positions.size());
    for (std::size_t v = 0; v < positions.size(); ++v) {
        const glm::dvec3 unit = normalized_or(normals[v], glm::dvec3(0.0, 0.0, 1.0));
        for (int c = 0; c < 3; ++c) {
            xyz.push_back(static_cast<float>(positions[v][c]));
            nrm.push_back(static_cast<float>(unit[c]));
        }
    }
    Document d;
    d.doc = {{"asset", {{"version", "2.0"}, {"generator", "Dualform"}}},
             {"scene", 0},
             {"scenes", json::array({{{"nodes", {0}}}})},
             {"nodes", json::array({{{"mesh", 0}, {"name", name}}})},
             {"buffers", json::array({json::object()})},
             {"bufferViews", json::array()},
             {"accessors", json::array()}};
    d.buffers.emplace_back();
    const int position = d.append_accessor(xyz, 3, true);
    const int normal = d.append_accessor(nrm, 3, false);
    std::string& b = d.buffers[0];
    const std::size_t offset = b.size();
    for (const Triangle& t : triangles) {
        for (std::uint32_t v : t) put_u32(b, v);
    }
    d.doc["bufferViews"].push_back({{"buffer", 0},
                                    {"byteOffset", offset},
                                    {"byteLength", 12 * triangles.size()},
                                    {"target", 34963}});
    d.doc["accessors"].push_back({{"bufferView", d.doc["bufferViews"].size() - 1},
                                  {"componentType", 5125},
                                  {"count", 3 * triangles.size()},
                                  {"type", "SCALAR"}});
    d.doc["meshes"] = json::array(
        {{{"name", name},
          {"primitives", json::array({{{"attributes", {{"POSITION", position}, {"NORMAL", normal}}},
                                       {"indices", d.doc["accessors"].size() - 1},
                                       {"mode", 4}}})}}});
    out = finish(d, binary);
}

}  // namespace dfm::mesh
