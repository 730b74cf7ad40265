#include "gltf_file.hpp"

#include <doctest/doctest.h>

#include <cstdint>
#include <cstring>

#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>

#include "support/test_files.hpp"

namespace dfm::test::gltf {

namespace {

std::uint32_t le32(const std::string& bytes, std::size_t at) {
    REQUIRE(at + 4 <= bytes.size());
    std::uint32_t v = 0;
    for (int i = 3; i >= 0; --i) v = (v << 8) | static_cast<unsigned char>(bytes[at + i]);
    return v;
}

std::string base64_decode(std::string_view text) {
    std::string out;
    std::uint32_t bits = 0;
    int count = 0;
    for (char c : text) {
        int v = 0;
        if (c >= 'A' && c <= 'Z')
            v = c - 'A';
        else if (c >= 'a' && c <= 'z')
            v = c - 'a' + 26;
        else if (c >= '0' && c <= '9')
            v = c - '0' + 52;
        else if (c == '+')
            v = 62;
        else if (c == '/')
            v = 63;
        else if (c == '=')
            break;
        else
            FAIL("a data URI holds a character outside base64: " << int(c));
        bits = (bits << 6) | static_cast<std::uint32_t>(v);
        if ((count += 6) >= 8) {
            count -= 8;
            out.push_back(static_cast<char>((bits >> count) & 0xff));
        }
    }
    return out;
}

json::JsonValue parse(std::string_view text, const std::filesystem::path& path) {
    json::JsonValue doc;
    const ToolStatus s = json::parse_json(text, path.string(), doc);
    REQUIRE_MESSAGE(s.is_ok(), s.message());
    REQUIRE(doc.type == json::JsonType::object);
    return doc;
}

std::size_t component_size(std::size_t type) {
    switch (type) {
        case 5120:
        case 5121: return 1;
        case 5122:
        case 5123: return 2;
        case 5125:
        case 5126: return 4;
    }
    FAIL("unknown componentType " << type);
    return 0;
}

std::size_t component_count(const std::string& type) {
    if (type == "SCALAR") return 1;
    if (type == "VEC2") return 2;
    if (type == "VEC3") return 3;
    if (type == "VEC4" || type == "MAT2") return 4;
    if (type == "MAT3") return 9;
    if (type == "MAT4") return 16;
    FAIL("unknown accessor type " << type);
    return 0;
}

glm::dmat4 local_matrix(const json::JsonValue& node) {
    if (const json::JsonMember* m = node.find("matrix")) {
        REQUIRE(m->value.items.size() == 16);
        glm::dmat4 out;
        for (int i = 0; i < 16; ++i) glm::value_ptr(out)[i] = m->value.items[i].number;
        return out;
    }
    glm::dvec3 t{0.0}, s{1.0};
    glm::dquat r{1.0, 0.0, 0.0, 0.0};
    if (const json::JsonMember* m = node.find("translation"))
        t = {m->value.items.at(0).number, m->value.items.at(1).number, m->value.items.at(2).number};
    if (const json::JsonMember* m = node.find("scale"))
        s = {m->value.items.at(0).number, m->value.items.at(1).number, m->value.items.at(2).number};
    if (const json::JsonMember* m = node.find("rotation"))  // x, y, z, w
        r = glm::dquat(m->value.items.at(3).number, m->value.items.at(0).number,
                       m->value.items.at(1).number, m->value.items.at(2).number);
    glm::dmat4 out = glm::mat4_cast(r);
    for (int c = 0; c < 3; ++c) out[c] *= s[c];
    out[3] = glm::dvec4(t, 1.0);
    return out;
}

}  // namespace

const json::JsonValue& member(const json::JsonValue& v, std::string_view key) {
    const json::JsonMember* m = v.find(key);
    REQUIRE_MESSAGE(m != nullptr, "no member " << std::string(key));
    return m->value;
}

std::size_t index_or(const json::JsonValue& v, std::string_view key, std::size_t fallback) {
    const json::JsonMember* m = v.find(key);
    return m ? static_cast<std::size_t>(m->value.number) : fallback;
}

Asset read_asset(const std::filesystem::path& path) {
    Asset a;
    a.path = path;
    const std::string bytes = read_text(path);
    std::string bin;
    bool glb = false;
    if (bytes.size() >= 12 && bytes.compare(0, 4, "glTF") == 0) {
        glb = true;
        REQUIRE(le32(bytes, 8) == bytes.size());
        const std::size_t json_size = le32(bytes, 12);
        REQUIRE(le32(bytes, 16) == 0x4E4F534Au);  // "JSON"
        a.doc = parse(std::string_view(bytes).substr(20, json_size), path);
        const std::size_t bin_at = 20 + json_size;
        if (bin_at < bytes.size()) {
            REQUIRE(le32(bytes, bin_at + 4) == 0x004E4942u);  // "BIN\0"
            bin = bytes.substr(bin_at + 8, le32(bytes, bin_at));
        }
    } else {
        a.doc = parse(bytes, path);
    }
    if (const json::JsonMember* buffers = a.doc.find("buffers")) {
        for (const json::JsonValue& b : buffers->value.items) {
            const json::JsonMember* uri = b.find("uri");
            std::string data;
            if (!uri) {
                REQUIRE_MESSAGE(glb, "a buffer without uri outside a GLB");
                data = bin;
            } else if (uri->value.text.rfind("data:", 0) == 0) {
                const std::size_t comma = uri->value.text.find(";base64,");
                REQUIRE(comma != std::string::npos);
                data = base64_decode(std::string_view(uri->value.text).substr(comma + 8));
            } else {
                data = read_text(path.parent_path() / uri->value.text);
            }
            REQUIRE(data.size() >= static_cast<std::size_t>(member(b, "byteLength").number));
            a.buffers.push_back(std::move(data));
        }
    }
    return a;
}

std::string accessor_bytes(const Asset& asset, std::size_t index) {
    const json::JsonValue& acc = member(asset.doc, "accessors").items.at(index);
    REQUIRE_MESSAGE(acc.find("sparse") == nullptr, "accessor " << index << " is sparse");
    const std::size_t element = component_size(index_or(acc, "componentType", 0)) *
                                component_count(member(acc, "type").text);
    const std::size_t count = index_or(acc, "count", 0);
    const json::JsonValue& view =
        member(asset.doc, "bufferViews").items.at(index_or(acc, "bufferView", 0));
    const std::string& buffer = asset.buffers.at(index_or(view, "buffer", 0));
    const std::size_t stride = index_or(view, "byteStride", element);
    const std::size_t start = index_or(view, "byteOffset", 0) + index_or(acc, "byteOffset", 0);
    std::string out;
    out.reserve(element * count);
    for (std::size_t i = 0; i < count; ++i) {
        REQUIRE(start + i * stride + element <= buffer.size());
        out.append(buffer, start + i * stride, element);
    }
    return out;
}

std::vector<double> accessor_floats(const Asset& asset, std::size_t index) {
    const json::JsonValue& acc = member(asset.doc, "accessors").items.at(index);
    REQUIRE(index_or(acc, "componentType", 0) == 5126);
    const std::string bytes = accessor_bytes(asset, index);
    std::vector<double> out(bytes.size() / 4);
    for (std::size_t i = 0; i < out.size(); ++i) {
        float f;
        std::memcpy(&f, bytes.data() + 4 * i, 4);
        out[i] = f;
    }
    return out;
}

std::size_t mesh_index(const Asset& asset, std::string_view name) {
    const auto& meshes = member(asset.doc, "meshes").items;
    for (std::size_t i = 0; i < meshes.size(); ++i) {
        const json::JsonMember* n = meshes[i].find("name");
        if (n && n->value.text == name) return i;
    }
    FAIL("no mesh named " << std::string(name) << " in " << asset.path);
    return 0;
}

glm::dmat4 mesh_world_matrix(const Asset& asset, std::size_t mesh) {
    const auto& nodes = member(asset.doc, "nodes").items;
    std::vector<std::size_t> parent(nodes.size(), nodes.size());
    for (std::size_t i = 0; i < nodes.size(); ++i)
        if (const json::JsonMember* c = nodes[i].find("children"))
            for (const json::JsonValue& child : c->value.items)
                parent.at(static_cast<std::size_t>(child.number)) = i;
    for (std::size_t i = 0; i < nodes.size(); ++i) {
        if (index_or(nodes[i], "mesh", nodes.size() + 1) != mesh) continue;
        glm::dmat4 m = local_matrix(nodes[i]);
        for (std::size_t p = parent[i]; p < nodes.size(); p = parent[p])
            m = local_matrix(nodes[p]) * m;
        return m;
    }
    FAIL("no node instances mesh " << mesh);
    return glm::dmat4{1.0};
}

std::vector<double> mesh_positions(const Asset& asset, std::size_t mesh) {
    std::vector<double> out;
    for (const json::JsonValue& prim :
         member(member(asset.doc, "meshes").items.at(mesh), "primitives").items) {
        const std::vector<double> p = accessor_floats(
            asset, static_cast<std::size_t>(member(member(prim, "attributes"), "POSITION").number));
        out.insert(out.end(), p.begin(), p.end());
    }
    return out;
}

std::vector<std::uint32_t> mesh_triangles(const Asset& asset, std::size_t mesh) {
    std::vector<std::uint32_t> out;
    std::uint32_t offset = 0;
    for (const json::JsonValue& prim :
         member(member(asset.doc, "meshes").items.at(mesh), "primitives").items) {
        REQUIRE(index_or(prim, "mode", 4) == 4);
        const std::size_t position =
            static_cast<std::size_t>(member(member(prim, "attributes"), "POSITION").number);
        const auto vertices = static_cast<std::uint32_t>(
            index_or(member(asset.doc, "accessors").items.at(position), "count", 0));
        const std::size_t indices = index_or(prim, "indices", SIZE_MAX);
        REQUIRE_MESSAGE(indices != SIZE_MAX, "a non-indexed primitive");
        const std::size_t type =
            index_or(member(asset.doc, "accessors").items.at(indices), "componentType", 0);
        const std::size_t width = component_size(type);
        const std::string bytes = accessor_bytes(asset, indices);
        for (std::size_t at = 0; at < bytes.size(); at += width) {
            std::uint32_t v = 0;
            for (std::size_t b = width; b-- > 0;)
                v = (v << 8) | static_cast<unsigned char>(bytes[at + b]);
            REQUIRE(v < vertices);
            out.push_back(offset + v);
        }
        offset += vertices;
    }
    return out;
}

std::vector<double> transformed(const glm::dmat4& m, const std::vector<double>& points) {
    std::vector<double> out(points.size());
    for (std::size_t i = 0; i + 2 < points.size(); i += 3) {
        const glm::dvec4 p = m * glm::dvec4(points[i], points[i + 1], points[i + 2], 1.0);
        out[i] = p.x;
        out[i + 1] = p.y;
        out[i + 2] = p.z;
    }
    return out;
}

}  // namespace dfm::test::gltf
