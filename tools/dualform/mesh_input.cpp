#include "dualform/mesh_input.hpp"

#include <cstdio>

#include "environment/host_environment.hpp"
#include "mesh/model_cache.hpp"

namespace dfm::cli {

Status load_mesh_input(std::string_view spec, mesh::Mesh& mesh, mesh::LoadReport& report) {
    std::filesystem::path path;
    if (Status s = mesh::resolve_mesh_spec(spec, {}, tools::models_folder_from_environment(), path);
        !s) {
        return s;
    }
    if (Status s = mesh::load_mesh(path, mesh, &report); !s) return s;
    for (const std::string& w : report.warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
    if (report.suppressed_warnings > 0) {
        std::fprintf(stderr, "warning: %zu more warnings not shown\n", report.suppressed_warnings);
    }
    return Status::ok();
}

}  // namespace dfm::cli
