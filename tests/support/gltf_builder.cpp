#include "support/gltf_builder.hpp"

#include <algorithm>
#include <cstring>
#include <fstream>

namespace dfm::test {

namespace {

std::string base64(const std::string& bytes) {
    static constexpr char digits[] =
        "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    for (std::size_t i = 0; i < bytes.size(); i += 3) {
        std::uint32_t triple = static_cast<unsigned char>(bytes[i]) << 16;
        if (i + 1 < bytes.size()) triple |= static_cast<unsigned char>(bytes[i + 1]) << 8;
        if (i + 2 < bytes.size()) triple |= static_cast<unsigned char>(bytes[i + 2]);
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

std::string join(const std::vector<std::string>& items) {
    std::string out;
    for (std::size_t i = 0; i < items.size(); ++i) {
        if (i > 0) out += ',';
        out += items[i];
    }
    return out;
}

}  // namespace

int GltfBuilder::view(const std::string& bytes, int stride) {
    while (bin_.size() % 4 != 0) bin_.push_back('\0');
    std::string v = "{\"buffer\":0,\"byteOffset\":" + std::to_string(bin_.size()) +
                    ",\"byteLength\":" + std::to_string(bytes.size());
    if (stride != 0) v += ",\"byteStride\":" + std::to_string(stride);
    views_.push_back(v + "}");
    bin_ += bytes;
    return static_cast<int>(views_.size()) - 1;
}

int GltfBuilder::accessor(int view, int component_type, std::size_t count, const std::string& type,
                          std::size_t byte_offset, const std::string& extra) {
    std::string a = "{";
    if (view >= 0) {
        a += "\"bufferView\":" + std::to_string(view) +
             ",\"byteOffset\":" + std::to_string(byte_offset) + ",";
    }
    a += "\"componentType\":" + std::to_string(component_type) +
         ",\"count\":" + std::to_string(count) + ",\"type\":\"" + type + "\"" + extra + "}";
    accessors_.push_back(a);
    return static_cast<int>(accessors_.size()) - 1;
}

int GltfBuilder::positions(const std::vector<float>& xyz) {
    float lo[3] = {1e30f, 1e30f, 1e30f}, hi[3] = {-1e30f, -1e30f, -1e30f};
    for (std::size_t i = 0; i < xyz.size(); ++i) {
        lo[i % 3] = std::min(lo[i % 3], xyz[i]);
        hi[i % 3] = std::max(hi[i % 3], xyz[i]);
    }
    const auto triple = [](const float* v) {
        std::string out = "[";
        for (int c = 0; c < 3; ++c) {
            if (c > 0) out += ',';
            out += std::to_string(v[c]);
        }
        out += ']';
        return out;
    };
    // Bounds printed with 6 decimals widened a little: they must contain
    // every value.
    float lo_w[3], hi_w[3];
    for (int c = 0; c < 3; ++c) {
        lo_w[c] = lo[c] - 1e-5f;
        hi_w[c] = hi[c] + 1e-5f;
    }
    return accessor(view_of(xyz), 5126, xyz.size() / 3, "VEC3", 0,
                    ",\"min\":" + triple(lo_w) + ",\"max\":" + triple(hi_w));
}

int GltfBuilder::floats(const std::vector<float>& values, const std::string& type) {
    const std::size_t n = type == "SCALAR" ? 1 : type == "VEC2" ? 2 : type == "VEC3" ? 3 : 4;
    return accessor(view_of(values), 5126, values.size() / n, type);
}

int GltfBuilder::indices_u8(const std::vector<std::uint8_t>& v) {
    return accessor(view_of(v), 5121, v.size(), "SCALAR");
}
int GltfBuilder::indices_u16(const std::vector<std::uint16_t>& v) {
    return accessor(view_of(v), 5123, v.size(), "SCALAR");
}
int GltfBuilder::indices_u32(const std::vector<std::uint32_t>& v) {
    return accessor(view_of(v), 5125, v.size(), "SCALAR");
}

std::string GltfBuilder::json(const std::string& buffer_uri) const {
    std::string buffer = "{\"byteLength\":" + std::to_string(bin_.size());
    if (!buffer_uri.empty()) buffer += ",\"uri\":\"" + buffer_uri + "\"";
    buffer += "}";
    std::string out = "{\"asset\":{\"version\":\"2.0\",\"generator\":\"dualform tests\"},";
    out += "\"buffers\":[" + buffer + "],\"bufferViews\":[" + join(views_) + "],\"accessors\":[" +
           join(accessors_) + "]";
    if (!members.empty()) out += "," + members;
    return out + "}";
}

std::string GltfBuilder::gltf_embedded() const {
    return json("data:application/octet-stream;base64," + base64(bin_));
}

std::string GltfBuilder::glb() const {
    std::string text = json("");
    while (text.size() % 4 != 0) text.push_back(' ');
    std::string bin = bin_;
    while (bin.size() % 4 != 0) bin.push_back('\0');
    std::string out = "glTF";
    put_u32(out, 2);
    put_u32(out, static_cast<std::uint32_t>(28 + text.size() + bin.size()));
    put_u32(out, static_cast<std::uint32_t>(text.size()));
    put_u32(out, 0x4E4F534Au);
    out += text;
    put_u32(out, static_cast<std::uint32_t>(bin.size()));
    put_u32(out, 0x004E4942u);
    return out + bin;
}

void GltfBuilder::write_external(const std::filesystem::path& gltf,
                                 const std::string& bin_name) const {
    std::ofstream(gltf, std::ios::binary) << json(bin_name);
    std::ofstream(gltf.parent_path() / bin_name, std::ios::binary) << bin_;
}

std::vector<float> float_positions(const mesh::Mesh& m) {
    std::vector<float> out;
    for (const glm::dvec3& p : m.positions) {
        for (int c = 0; c < 3; ++c) out.push_back(static_cast<float>(p[c]));
    }
    return out;
}

mesh::Mesh split_corners(const mesh::Mesh& m, bool (*split)(std::size_t face)) {
    mesh::Mesh out;
    out.positions = m.positions;
    std::vector<bool> used(m.positions.size(), false);
    for (std::size_t t = 0; t < m.triangles.size(); ++t) {
        mesh::Triangle tri = m.triangles[t];
        const bool own = split(t);
        for (std::uint32_t& v : tri) {
            // A vertex's first face keeps it, so no original is left unused.
            if (own && used[v]) {
                out.positions.push_back(m.positions[v]);
                v = static_cast<std::uint32_t>(out.positions.size() - 1);
            } else {
                used[v] = true;
            }
        }
        out.triangles.push_back(tri);
    }
    return out;
}

mesh::Mesh rounded_to_float(const mesh::Mesh& m) {
    mesh::Mesh out = m;
    for (glm::dvec3& p : out.positions) {
        for (int c = 0; c < 3; ++c) {
            // Through a float in memory: GCC 12 at -O3 was seen to drop a
            // double -> float -> double round trip on glm vectors.
            volatile float f = static_cast<float>(p[c]);
            p[c] = f;
        }
    }
    return out;
}

}  // namespace dfm::test
