#include "core/number_text.hpp"
#include "mesh/write.hpp"

namespace dfm::mesh {

void write_off(const Mesh& mesh, std::string& out) {
    out = "OFF\n" + std::to_string(mesh.vertex_count()) + ' ' + std::to_string(mesh.face_count()) +
          " 0\n";
    for (const glm::dvec3& p : mesh.positions) {
        append_numbers(out, p);
        out += '\n';
    }
    for (const Triangle& t : mesh.triangles) {
        out += "3 " + std::to_string(t[0]) + ' ' + std::to_string(t[1]) + ' ' +
               std::to_string(t[2]) + '\n';
    }
}

}  // namespace dfm::mesh
