#include <bit>
#include <cstring>

#include "core/number_text.hpp"
#include "mesh/write.hpp"

namespace dfm::mesh {

namespace {

class BinaryOut {
public:
    BinaryOut(std::string& out, bool big_endian)
        : out_(out), swap_(big_endian != (std::endian::native == std::endian::big)) {}

    template <typename T>
    void put(T value) {
        unsigned char raw[sizeof(T)];
        std::memcpy(raw, &value, sizeof(T));
        if (swap_) {
            for (std::size_t i = 0; i < sizeof(T) / 2; ++i)
                std::swap(raw[i], raw[sizeof(T) - 1 - i]);
        }
        out_.append(reinterpret_cast<const char*>(raw), sizeof(T));
    }

private:
    std::string& out_;
    bool swap_;
};

const char* encoding_name(PlyEncoding e) {
    switch (e) {
        case PlyEncoding::binary_little_endian: return "binary_little_endian";
        case PlyEncoding::binary_big_endian: return "binary_big_endian";
        case PlyEncoding::ascii: return "ascii";
    }
    return "ascii";
}

}  // namespace

void write_ply(const Mesh& mesh, const WriteOptions& options, std::string& out) {
    const char* scalar = options.ply_double ? "double" : "float";
    out = std::string("ply\nformat ") + encoding_name(options.ply_encoding) +
          " 1.0\ncomment written by dualform\nelement vertex " +
          std::to_string(mesh.vertex_count()) + "\nproperty " + scalar + " x\nproperty " + scalar +
          " y\nproperty " + scalar + " z\nelement face " + std::to_string(mesh.face_count()) +
          "\nproperty list uchar uint vertex_indices\nend_header\n";

    if (options.ply_encoding == PlyEncoding::ascii) {
        for (const glm::dvec3& p : mesh.positions) {
            for (int c = 0; c < 3; ++c) {
                if (c > 0) out += ' ';
                append_number(out, options.ply_double ? p[c] : static_cast<float>(p[c]));
            }
            out += '\n';
        }
        for (const Triangle& t : mesh.triangles) {
            out += "3 " + std::to_string(t[0]) + ' ' + std::to_string(t[1]) + ' ' +
                   std::to_string(t[2]) + '\n';
        }
        return;
    }

    BinaryOut bin(out, options.ply_encoding == PlyEncoding::binary_big_endian);
    for (const glm::dvec3& p : mesh.positions) {
        for (int c = 0; c < 3; ++c) {
            if (options.ply_double) {
                bin.put(p[c]);
            } else {
                bin.put(static_cast<float>(p[c]));
            }
        }
    }
    for (const Triangle& t : mesh.triangles) {
        bin.put(static_cast<std::uint8_t>(3));
        for (std::uint32_t v : t) bin.put(v);
    }
}

}  // namespace dfm::mesh
