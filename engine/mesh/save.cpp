#include <cerrno>
#include <cstring>
#include <fstream>
#include <new>

#include "mesh/gltf_io.hpp"
#include "mesh/write.hpp"

namespace dfm::mesh {

Status save_mesh(const std::filesystem::path& path, const Mesh& mesh, const WriteOptions& options) {
    const std::string name = path.string();
    const std::optional<FileFormat> format = format_from_extension(path);
    if (!format) {
        return Status(
            Errc::unsupported,
            name + ": unknown mesh format (expected .off, .obj, .ply, .gltf, .glb or .fbx)");
    }
    try {
        std::string bytes;
        switch (*format) {
            case FileFormat::off: write_off(mesh, bytes); break;
            case FileFormat::obj: write_obj(mesh, options, bytes); break;
            case FileFormat::ply: write_ply(mesh, options, bytes); break;
            case FileFormat::gltf:
                write_fresh_gltf(mesh.positions, mesh.triangles, path.stem().string(),
                                 path.extension() == ".glb" || path.extension() == ".GLB", bytes);
                break;
            case FileFormat::fbx:
                return Status(Errc::unsupported,
                              name +
                                  ": FBX is written only back into the FBX file a mesh was "
                                  "loaded from (docs/fbx.md)");
        }
        return write_file_atomically(path, bytes);
    } catch (const std::bad_alloc&) {
        return Status(Errc::out_of_memory, name + ": out of memory while writing");
    }
}

Status write_file_atomically(const std::filesystem::path& path, const std::string& bytes) {
    const std::string name = path.string();
    try {
        std::filesystem::path temp = path;
        temp += ".partial";
        {
            std::ofstream out(temp, std::ios::binary | std::ios::trunc);
            if (!out)
                return Status(Errc::io_error, name + ": cannot create: " + std::strerror(errno));
            out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
            out.close();
            if (!out) {
                std::error_code ignored;
                std::filesystem::remove(temp, ignored);
                return Status(Errc::io_error, name + ": write failed: " + std::strerror(errno));
            }
        }
        std::error_code ec;
        std::filesystem::rename(temp, path, ec);
        if (ec) {
            std::filesystem::remove(temp, ec);
            return Status(Errc::io_error, name + ": cannot replace: " + ec.message());
        }
        return Status::ok();
    } catch (const std::bad_alloc&) {
        return Status(Errc::out_of_memory, name + ": out of memory while writing");
    }
}

}  // namespace dfm::mesh
