#include "support/real_models.hpp"

#include <doctest/doctest.h>

#include <filesystem>

#include "environment/host_environment.hpp"
#include "mesh/load.hpp"
#include "mesh/model_cache.hpp"
#include "roi/ball_selection.hpp"

namespace dfm::test {

deform::MeshModel load_real_model(const std::string& name) {
    std::filesystem::path path;
    const Status r =
        mesh::resolve_mesh_spec("model:" + name, {}, tools::models_folder_from_environment(), path);
    REQUIRE_MESSAGE(r.is_ok(), r.message());
    mesh::Mesh m;
    const Status s = mesh::load_mesh(path, m);
    REQUIRE_MESSAGE(s.is_ok(), s.message());
    return deform::build_mesh_model(std::move(m));
}

std::vector<std::uint32_t> ball_around(const deform::MeshModel& model, std::uint32_t center,
                                       double radius) {
    std::vector<std::uint32_t> out;
    REQUIRE(roi::select_ball(model.mesh.positions, model.vertex_neighbors, center,
                             radius * model.diagonal, out)
                .is_ok());
    return out;
}

}  // namespace dfm::test
