#include "mesh/host_mesh.hpp"

#include <new>

#include "mesh/fbx_host.hpp"
#include "mesh/gltf_io.hpp"
#include "mesh/skin_weld.hpp"

namespace dfm::mesh {

Status load_host_mesh(const std::filesystem::path& spec, Mesh& surface, HostMesh& host,
                      LoadReport* report, const std::filesystem::path& reference_folder,
                      const WeldOptions& weld) {
    surface = Mesh{};
    host = HostMesh{};
    std::string file, selector;
    split_gltf_spec(spec.string(), file, selector);
    const std::filesystem::path path(file);
    const std::optional<FileFormat> format = format_from_extension(path);
    const std::optional<FileFormat> whole = format_from_extension(spec);
    if (format != FileFormat::gltf && whole != FileFormat::fbx) {
        return load_mesh(spec, surface, report);
    }
    LoadReport local;
    LoadReport& r = report ? *report : local;
    r = LoadReport{};
    try {
        if (whole == FileFormat::fbx) {
            std::string bytes;
            if (Status s = read_file_bytes(spec, bytes); !s) return s;
            return load_fbx_host(std::move(bytes), spec.string(), weld, surface, host, r);
        }
        std::string bytes;
        if (Status s = read_file_bytes(path, bytes); !s) return s;
        const ExternalFiles files{path.parent_path().empty() ? "." : path.parent_path(),
                                  reference_folder};
        Mesh split;
        auto asset = std::make_shared<GltfAsset>();
        Skin skin;
        if (Status s = read_gltf(bytes, path.string(), &files, selector, split, *asset, skin, r);
            !s) {
            return s;
        }
        auto welded = std::make_shared<SeamWeld>();
        weld_skinned(split, skin, WeldBy::skin, weld, path.string(), surface, *welded, host.skin,
                     r);
        host.weld = std::move(welded);
        host.gltf = std::move(asset);
        return Status::ok();
    } catch (const std::bad_alloc&) {
        surface = Mesh{};
        host = HostMesh{};
        return Status(Errc::out_of_memory, path.string() + ": out of memory while loading");
    }
}

std::vector<glm::dvec3> host_positions(const Mesh& surface, const HostMesh& host) {
    if (!host.weld) return surface.positions;
    std::vector<glm::dvec3> out(host.weld->host_vertex_count());
    for (std::size_t v = 0; v < out.size(); ++v) {
        out[v] = surface.positions[host.weld->surface_of[v]];
    }
    return out;
}

Status save_host_mesh(const std::filesystem::path& path, const Mesh& bind, const Mesh& shown,
                      const HostMesh& host, const WriteOptions& options) {
    const std::string name = path.string();
    const std::optional<FileFormat> format = format_from_extension(path);
    const bool gltf = format == FileFormat::gltf;
    const bool fbx = format == FileFormat::fbx;
    if (fbx && !host.fbx) {
        return Status(Errc::unsupported,
                      name +
                          ": FBX is written only back into the FBX file the mesh was loaded "
                          "from (docs/fbx.md)");
    }
    if (!options.morph_target.empty() && !(gltf && host.gltf) && !(fbx && host.fbx)) {
        return Status(Errc::unsupported,
                      name +
                          ": a morph target is written only to .gltf or .glb for a mesh loaded "
                          "from glTF, or to .fbx for one loaded from FBX (it is the difference "
                          "from that asset)");
    }
    if (fbx) return save_fbx_host(path, bind, host, options);
    if (!gltf || !host.weld) return save_mesh(path, shown, options);
    try {
        const bool binary = path.extension() == ".glb" || path.extension() == ".GLB";
        std::string bytes;
        if (host.gltf) {
            const std::vector<glm::dvec3> positions = host_positions(bind, host);
            if (Status s =
                    write_gltf(*host.gltf, positions, host.weld->host_triangles,
                               options.morph_target, options.morph_target_extras, binary, bytes);
                !s) {
                return Status(s.code(), name + ": " + s.message());
            }
        } else {
            write_fresh_gltf(host_positions(shown, host), host.weld->host_triangles,
                             path.stem().string(), binary, bytes);
        }
        return write_file_atomically(path, bytes);
    } catch (const std::bad_alloc&) {
        return Status(Errc::out_of_memory, name + ": out of memory while writing");
    }
}

}  // namespace dfm::mesh
