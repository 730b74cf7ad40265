#include "mesh/fbx_host.hpp"

// The build without Assimp (DUALFORM_FBX off): FBX is recognised and refused.
namespace dfm::mesh {

namespace {

const char* const why =
    "this build of Dualform reads and writes no FBX (it was built without Assimp: "
    "DUALFORM_FBX; docs/fbx.md)";

}  // namespace

bool fbx_supported() {
    return false;
}

Status load_fbx_host(std::string, std::string_view source, const WeldOptions&, Mesh& surface,
                     HostMesh& host, LoadReport&) {
    surface = Mesh{};
    host = HostMesh{};
    return Status(Errc::unsupported, std::string(source) + ": " + why);
}

Status save_fbx_host(const std::filesystem::path& path, const Mesh&, const HostMesh&,
                     const WriteOptions&) {
    return Status(Errc::unsupported, path.string() + ": " + why);
}

}  // namespace dfm::mesh
