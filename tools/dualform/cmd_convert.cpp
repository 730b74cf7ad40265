#include <cstdio>
#include <string>

#include <vector>

#include "dualform/c_api.hpp"
#include "dualform/commands.hpp"
#include "dualform/usage.hpp"

namespace dfm::cli {

int run_convert(std::span<const std::string_view> args) {
    std::vector<std::string_view> paths;
    dfm_save_options options = {};
    for (std::size_t i = 0; i < args.size(); ++i) {
        const std::string_view a = args[i];
        if (a == "--ply") {
            if (i + 1 >= args.size()) return bad_input("--ply needs an encoding");
            const std::string_view e = args[++i];
            if (e == "ascii") {
                options.ply_encoding = DFM_PLY_ASCII;
            } else if (e == "binary_little_endian") {
                options.ply_encoding = DFM_PLY_BINARY_LITTLE_ENDIAN;
            } else if (e == "binary_big_endian") {
                options.ply_encoding = DFM_PLY_BINARY_BIG_ENDIAN;
            } else {
                return bad_input("--ply: unknown encoding '" + std::string(e) + "'");
            }
        } else if (a == "--ply-float") {
            options.ply_float = true;
        } else if (a == "--obj-normals") {
            options.obj_normals = true;
        } else if (a.starts_with("--")) {
            return bad_input("unknown option '" + std::string(a) + "'\n" + usage(convert_help));
        } else {
            paths.push_back(a);
        }
    }
    if (paths.size() != 2) return bad_input(usage(convert_help));
    ContextPtr context;
    if (ToolStatus s = create_context(context); !s) return bad_input(s.message());
    const std::string in(paths[0]);
    const std::string out(paths[1]);
    dfm_mesh* handle = nullptr;
    if (ToolStatus s = api_status(dfm_mesh_load(context.get(), in.c_str(), &handle)); !s) {
        return bad_input(s.message());
    }
    const MeshPtr mesh(handle);
    if (ToolStatus s = api_status(dfm_mesh_save_with_options(mesh.get(), out.c_str(), &options));
        !s) {
        return work_failure(s);
    }
    return exit_ok;
}

}  // namespace dfm::cli
