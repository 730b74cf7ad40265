#pragma once

#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "core/status.hpp"
#include "mesh/mesh.hpp"

namespace dfm::mesh {

enum class FileFormat { off, obj, ply, gltf, fbx };  // gltf: .gltf and .glb

const char* format_name(FileFormat format);

// What a load found that was not fatal. Element numbers in messages are
// 0-based and count in file order; lines are 1-based.
struct LoadReport {
    std::size_t polygons = 0;               // faces as the file lists them
    std::size_t triangulated_polygons = 0;  // polygons of more than three corners, fanned
    std::size_t dropped_faces = 0;          // triangles dropped for repeating a vertex
    std::vector<std::string> warnings;      // the first max_warnings, each located
    std::size_t suppressed_warnings = 0;    // warnings beyond those

    static constexpr std::size_t max_warnings = 20;

    // Keeps `what` among the first max_warnings, or counts it beyond them.
    void warn(std::string what) {
        if (warnings.size() < max_warnings) {
            warnings.push_back(std::move(what));
        } else {
            ++suppressed_warnings;
        }
    }
};

// Loads an OFF, OBJ, PLY, glTF (.gltf, .glb, optionally with "#mesh=NAME";
// split copies welded exactly) or FBX file (binary or ASCII 7.x, read
// through Assimp where the build has it; docs/fbx.md); see host_mesh.hpp
// for the host's numbering. The format comes from the extension, or from the
// first bytes when the extension says nothing. On failure `out` is left
// empty and the status names the file, the line (or byte offset) and the
// element. Never throws. Only glTF follows references to other files (its
// external buffers), and only inside the file's own folder (gltf_io.hpp);
// OBJ's mtllib and usemtl are skipped, OFF and PLY have none.
Status load_mesh(const std::filesystem::path& path, Mesh& out, LoadReport* report = nullptr);

// Parses a mesh held in memory; `source` names it in messages. glTF from
// bytes may not use external buffers.
Status parse_mesh(std::string_view bytes, FileFormat format, std::string_view source, Mesh& out,
                  LoadReport* report = nullptr);

std::optional<FileFormat> format_from_extension(const std::filesystem::path& path);
std::optional<FileFormat> format_from_content(std::string_view head);

// Whether this build reads and writes FBX (DUALFORM_FBX: built with Assimp).
bool fbx_supported();

// A file's whole contents; the status names the file and what failed.
Status read_file_bytes(const std::filesystem::path& path, std::string& bytes);

}  // namespace dfm::mesh
