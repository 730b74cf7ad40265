#include "mesh/load.hpp"

#include <cerrno>
#include <cstring>
#include <fstream>
#include <new>

#include "mesh/fbx_document.hpp"
#include "mesh/fbx_host.hpp"
#include "mesh/gltf_io.hpp"
#include "mesh/host_mesh.hpp"
#include "mesh/mesh_builder.hpp"
#include "mesh/readers.hpp"
#include "mesh/skin_weld.hpp"

namespace dfm::mesh {

const char* format_name(FileFormat format) {
    switch (format) {
        case FileFormat::off: return "OFF";
        case FileFormat::obj: return "OBJ";
        case FileFormat::ply: return "PLY";
        case FileFormat::gltf: return "glTF";
        case FileFormat::fbx: return "FBX";
    }
    return "unknown";
}

std::optional<FileFormat> format_from_extension(const std::filesystem::path& path) {
    std::string ext = path.extension().string();
    for (char& c : ext) c = static_cast<char>(c >= 'A' && c <= 'Z' ? c - 'A' + 'a' : c);
    if (ext == ".off") return FileFormat::off;
    if (ext == ".obj") return FileFormat::obj;
    if (ext == ".ply") return FileFormat::ply;
    if (ext == ".gltf" || ext == ".glb") return FileFormat::gltf;
    if (ext == ".fbx") return FileFormat::fbx;
    return std::nullopt;
}

std::optional<FileFormat> format_from_content(std::string_view head) {
    if (head.starts_with("glTF")) return FileFormat::gltf;
    if (looks_like_fbx(head)) return FileFormat::fbx;
    if (head.starts_with("ply\n") || head.starts_with("ply\r\n")) return FileFormat::ply;
    for (std::string_view key : {"OFF", "COFF", "NOFF", "CNOFF", "STOFF", "STCOFF", "STNOFF"}) {
        if (head.starts_with(key) && (head.size() == key.size() || head[key.size()] == ' ' ||
                                      head[key.size()] == '\n' || head[key.size()] == '\r')) {
            return FileFormat::off;
        }
    }
    return std::nullopt;
}

namespace {

// The file a glTF spec names, when the spec is one ("cow.glb#mesh=body");
// any other path comes back empty.
std::filesystem::path gltf_file_of(const std::filesystem::path& spec) {
    std::string file, selector;
    split_gltf_spec(spec.string(), file, selector);
    const std::filesystem::path p(file);
    const auto format = format_from_extension(p);
    return format == FileFormat::gltf ? p : std::filesystem::path();
}

}  // namespace

Status read_file_bytes(const std::filesystem::path& path, std::string& bytes) {
    const std::string name = path.string();
    std::error_code ec;
    const std::filesystem::file_status st = std::filesystem::status(path, ec);
    if (ec || !std::filesystem::exists(st)) {
        return Status(Errc::not_found, name + ": no such file");
    }
    if (std::filesystem::is_directory(st)) {
        return Status(Errc::io_error, name + ": is a directory, not a mesh file");
    }
    std::ifstream in(path, std::ios::binary);
    if (!in) {
        return Status(Errc::io_error, name + ": cannot open: " + std::strerror(errno));
    }
    in.seekg(0, std::ios::end);
    const std::streamoff size = in.tellg();
    in.seekg(0, std::ios::beg);
    if (size < 0) return Status(Errc::io_error, name + ": cannot tell the file's size");
    bytes.resize(static_cast<std::size_t>(size));
    in.read(bytes.data(), size);
    if (in.gcount() != size) {
        return Status(Errc::io_error,
                      name + ": read failed after " + std::to_string(in.gcount()) + " bytes");
    }
    if (bytes.empty()) return Status(Errc::parse_error, name + ": the file is empty");
    return Status::ok();
}

Status parse_mesh(std::string_view bytes, FileFormat format, std::string_view source, Mesh& out,
                  LoadReport* report) {
    out = Mesh{};
    LoadReport local;
    LoadReport& r = report ? *report : local;
    r = LoadReport{};
    try {
        if (format == FileFormat::gltf) {
            Mesh host;
            GltfAsset asset;
            Skin skin;
            if (Status s = read_gltf(bytes, source, nullptr, "", host, asset, skin, r); !s) {
                return s;
            }
            SeamWeld weld;
            std::shared_ptr<const Skin> surface_skin;
            weld_skinned(host, skin, WeldBy::skin, {}, std::string(source), out, weld, surface_skin,
                         r);
            return Status::ok();
        }
        if (format == FileFormat::fbx) {
            HostMesh host;
            return load_fbx_host(std::string(bytes), source, {}, out, host, r);
        }
        MeshBuilder builder(r);
        Status s;
        switch (format) {
            case FileFormat::off: s = read_off(bytes, source, builder); break;
            case FileFormat::obj: s = read_obj(bytes, source, builder); break;
            case FileFormat::ply: s = read_ply(bytes, source, builder); break;
            case FileFormat::gltf:
            case FileFormat::fbx: break;
        }
        if (!s) return s;
        out = builder.take();
        return Status::ok();
    } catch (const std::bad_alloc&) {
        out = Mesh{};
        return Status(Errc::out_of_memory, std::string(source) + ": out of memory while loading");
    }
}

Status load_mesh(const std::filesystem::path& path, Mesh& out, LoadReport* report) {
    out = Mesh{};
    if (format_from_extension(gltf_file_of(path)) ||
        format_from_extension(path) == FileFormat::fbx) {
        HostMesh host;
        return load_host_mesh(path, out, host, report);
    }
    try {
        std::string bytes;
        if (Status s = read_file_bytes(path, bytes); !s) return s;
        std::optional<FileFormat> format = format_from_extension(path);
        if (!format) format = format_from_content(bytes);
        if (!format) {
            return Status(
                Errc::unsupported,
                path.string() +
                    ": unknown mesh format (expected .off, .obj, .ply, .gltf, .glb or .fbx)");
        }
        return parse_mesh(bytes, *format, path.string(), out, report);
    } catch (const std::bad_alloc&) {
        out = Mesh{};
        return Status(Errc::out_of_memory, path.string() + ": out of memory while reading");
    }
}

}  // namespace dfm::mesh
