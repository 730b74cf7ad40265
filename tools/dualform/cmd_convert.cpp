#include <cstdio>
#include <string>

#include "dualform/commands.hpp"
#include "dualform/mesh_input.hpp"
#include "mesh/write.hpp"

namespace dfm::cli {

namespace {

constexpr const char* usage =
    "usage: dualform convert IN OUT [--ply ascii|binary_little_endian|binary_big_endian] "
    "[--ply-float] [--obj-normals]";

}  // namespace

int run_convert(std::span<const std::string_view> args) {
    std::vector<std::string_view> paths;
    mesh::WriteOptions options;
    for (std::size_t i = 0; i < args.size(); ++i) {
        const std::string_view a = args[i];
        if (a == "--ply") {
            if (i + 1 >= args.size()) return bad_input("--ply needs an encoding");
            const std::string_view e = args[++i];
            if (e == "ascii") {
                options.ply_encoding = mesh::PlyEncoding::ascii;
            } else if (e == "binary_little_endian") {
                options.ply_encoding = mesh::PlyEncoding::binary_little_endian;
            } else if (e == "binary_big_endian") {
                options.ply_encoding = mesh::PlyEncoding::binary_big_endian;
            } else {
                return bad_input("--ply: unknown encoding '" + std::string(e) + "'");
            }
        } else if (a == "--ply-float") {
            options.ply_double = false;
        } else if (a == "--obj-normals") {
            options.obj_normals = true;
        } else if (a.starts_with("--")) {
            return bad_input("unknown option '" + std::string(a) + "'\n" + usage);
        } else {
            paths.push_back(a);
        }
    }
    if (paths.size() != 2) return bad_input(usage);
    mesh::Mesh m;
    mesh::LoadReport report;
    if (Status s = load_mesh_input(paths[0], m, report); !s) return bad_input(s.message());
    if (Status s = mesh::save_mesh(std::string(paths[1]), m, options); !s) {
        return bad_input(s.message());
    }
    return exit_ok;
}

}  // namespace dfm::cli
