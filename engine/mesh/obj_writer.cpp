#include "core/number_text.hpp"
#include "mesh/normals.hpp"
#include "mesh/write.hpp"

namespace dfm::mesh {

namespace {

void append_vector(std::string& out, const char* keyword, const glm::dvec3& v) {
    out += keyword;
    out += ' ';
    append_numbers(out, v);
    out += '\n';
}

}  // namespace

void write_obj(const Mesh& mesh, const WriteOptions& options, std::string& out) {
    out = "# written by dualform\n";
    for (const glm::dvec3& p : mesh.positions) append_vector(out, "v", p);
    if (options.obj_normals) {
        std::vector<glm::dvec3> normals;
        compute_vertex_normals(mesh, mesh.positions, normals);
        for (const glm::dvec3& n : normals) append_vector(out, "vn", n);
    }
    for (const Triangle& t : mesh.triangles) {
        out += 'f';
        for (std::uint32_t v : t) {
            const std::string i = std::to_string(v + 1);
            out += ' ' + i;
            if (options.obj_normals) out += "//" + i;
        }
        out += '\n';
    }
}

}  // namespace dfm::mesh
