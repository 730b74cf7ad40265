#include "support/model_variants.hpp"

#include <string>

#include "core/number_text.hpp"
#include "mesh/write.hpp"
#include "support/test_files.hpp"

namespace dfm::test {

namespace {

// OBJ by hand, for the corner forms our writer does not produce: a texture
// coordinate and a normal per vertex, referenced as v/vt/vn, and negative
// indices counted back from the last vertex.
std::string obj_text(const mesh::Mesh& m, bool negative) {
    std::string out = "# cow with texture coordinates and normals\ng body\n";
    for (const glm::dvec3& p : m.positions) {
        out += "v ";
        append_numbers(out, p);
        out += "\nvt ";
        append_number(out, p.x);
        out += ' ';
        append_number(out, p.y);
        out += "\nvn 0 0 1\n";
    }
    const auto n = static_cast<long long>(m.vertex_count());
    for (const mesh::Triangle& t : m.triangles) {
        out += 'f';
        for (std::uint32_t v : t) {
            const long long i = negative ? static_cast<long long>(v) - n : v + 1;
            const std::string s = std::to_string(i);
            out += ' ' + s + '/' + s + '/' + s;
        }
        out += '\n';
    }
    return out;
}

}  // namespace

std::vector<std::filesystem::path> write_model_variants(const mesh::Mesh& m,
                                                        const std::filesystem::path& dir) {
    std::vector<std::filesystem::path> files = {dir / "vt_vn.obj", dir / "negative.obj"};
    write_text(files[0], obj_text(m, false));
    write_text(files[1], obj_text(m, true));
    struct Saved {
        const char* name;
        mesh::WriteOptions options;
    };
    for (const Saved& s :
         {Saved{"normals.obj", {.obj_normals = true}},
          Saved{"ascii.ply", {.ply_encoding = mesh::PlyEncoding::ascii}},
          Saved{"le.ply", {.ply_encoding = mesh::PlyEncoding::binary_little_endian}},
          Saved{"be.ply", {.ply_encoding = mesh::PlyEncoding::binary_big_endian}}}) {
        files.push_back(dir / s.name);
        const Status st = mesh::save_mesh(files.back(), m, s.options);
        if (!st) throw std::runtime_error(st.message());
    }
    return files;
}

}  // namespace dfm::test
