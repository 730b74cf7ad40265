#include <doctest/doctest.h>

#include <cstdint>
#include <random>
#include <string>

#include "mesh/gltf_io.hpp"
#include "mesh/load.hpp"
#include "mesh/write.hpp"
#include "support/procedural_meshes.hpp"

// Damaged input of every format must give a clean status: no crash, no hang,
// no sanitizer report, and on failure an empty mesh and a located message.
using namespace dfm::mesh;

namespace {

struct Encoded {
    const char* name;
    FileFormat format;
    std::string bytes;
};

std::vector<Encoded> encodings() {
    Mesh m = dfm::test::make_limb(5, 2, 0.5, 1.0);
    std::vector<Encoded> out;
    std::string bytes;
    write_off(m, bytes);
    out.push_back({"limb.off", FileFormat::off, bytes});
    write_obj(m, {.obj_normals = true}, bytes);
    out.push_back({"limb.obj", FileFormat::obj, bytes});
    for (PlyEncoding e :
         {PlyEncoding::ascii, PlyEncoding::binary_little_endian, PlyEncoding::binary_big_endian}) {
        write_ply(m, {.ply_encoding = e, .ply_double = false}, bytes);
        out.push_back({"limb.ply", FileFormat::ply, bytes});
    }
    for (const bool binary : {true, false}) {
        write_fresh_gltf(m.positions, m.triangles, "mesh", binary, bytes);
        out.push_back({binary ? "limb.glb" : "limb.gltf", FileFormat::gltf, bytes});
    }
    return out;
}

void check_clean(const Encoded& e, std::string_view bytes) {
    Mesh m;
    const dfm::Status s = parse_mesh(bytes, e.format, e.name, m);
    if (s.is_ok()) {
        for (const Triangle& t : m.triangles) {
            for (std::uint32_t v : t) REQUIRE(v < m.vertex_count());
        }
    } else {
        REQUIRE(m.vertex_count() == 0);
        REQUIRE(m.face_count() == 0);
        std::string prefix = e.name;
        prefix += ':';
        REQUIRE(s.message().rfind(prefix, 0) == 0);
    }
}

}  // namespace

TEST_CASE("every truncation of every format loads cleanly or fails cleanly") {
    for (const Encoded& e : encodings()) {
        CAPTURE(e.bytes.substr(0, 40));
        for (std::size_t n = 0; n < e.bytes.size(); ++n) {
            CAPTURE(n);
            check_clean(e, std::string_view(e.bytes).substr(0, n));
        }
    }
}

TEST_CASE("random byte damage loads cleanly or fails cleanly") {
    std::mt19937 rng(20261122);
    const char interesting[] = {'\0', '\n', ' ', '#', '-', '/', '9', 'e', '.', '\xff', 'n', '\r'};
    for (const Encoded& e : encodings()) {
        CAPTURE(e.bytes.substr(0, 40));
        for (int trial = 0; trial < 1500; ++trial) {
            std::string bytes = e.bytes;
            const int edits = 1 + static_cast<int>(rng() % 4);
            for (int k = 0; k < edits; ++k) {
                const std::size_t at = rng() % bytes.size();
                switch (rng() % 3) {
                    case 0: bytes[at] = interesting[rng() % sizeof interesting]; break;
                    case 1: bytes[at] = static_cast<char>(rng()); break;
                    default:
                        if (bytes.size() > 8) bytes.erase(at % (bytes.size() - 8), 1 + rng() % 8);
                        break;
                }
            }
            CAPTURE(trial);
            check_clean(e, bytes);
        }
    }
}
