#include "mesh/fbx_host.hpp"

#include <memory>
#include <new>

#include "mesh/fbx_io.hpp"
#include "mesh/skin_weld.hpp"

namespace dfm::mesh {

bool fbx_supported() {
    return true;
}

Status load_fbx_host(std::string bytes, std::string_view source, const WeldOptions& weld,
                     Mesh& surface, HostMesh& host, LoadReport& report) {
    surface = Mesh{};
    host = HostMesh{};
    Mesh control_points;
    auto asset = std::make_shared<FbxAsset>();
    Skin skin;
    if (Status s = read_fbx(std::move(bytes), source, control_points, *asset, skin, report); !s) {
        return s;
    }
    auto welded = std::make_shared<SeamWeld>();
    // Coincident control points that faces connect join only where their
    // skin and their morph deltas agree.
    weld_skinned(control_points, skin, WeldBy::skin_and_morphs, weld, std::string(source), surface,
                 *welded, host.skin, report);
    host.weld = std::move(welded);
    host.fbx = std::move(asset);
    return Status::ok();
}

Status save_fbx_host(const std::filesystem::path& path, const Mesh& bind, const HostMesh& host,
                     const WriteOptions& options) {
    const std::string name = path.string();
    try {
        std::string bytes;
        if (Status s = write_fbx(*host.fbx, host_positions(bind, host), options.morph_target,
                                 options.morph_target_extras, bytes);
            !s) {
            return Status(s.code(), name + ": " + s.message());
        }
        return write_file_atomically(path, bytes);
    } catch (const std::bad_alloc&) {
        return Status(Errc::out_of_memory, name + ": out of memory while writing");
    }
}

}  // namespace dfm::mesh
