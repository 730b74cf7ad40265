#include "mesh/model_cache.hpp"

#include <string>

namespace dfm::mesh {

Status resolve_mesh_spec(std::string_view spec, const std::filesystem::path& base,
                         const std::filesystem::path& models_directory,
                         std::filesystem::path& out) {
    constexpr std::string_view prefix = "model:";
    if (!spec.starts_with(prefix)) {
        const std::filesystem::path p(spec);
        out = p.is_absolute() || base.empty() ? p : base / p;
        return Status::ok();
    }
    const std::string_view name = spec.substr(prefix.size());
    std::string quoted = "'";
    quoted.append(spec);
    quoted += "': ";
    const bool plain = !name.empty() && name.find_first_of("/\\") == std::string_view::npos &&
                       name != "." && name != "..";
    if (!plain) {
        return Status(Errc::invalid_argument,
                      quoted + "a model name is a plain file name, like model:cow");
    }
    if (models_directory.empty()) {
        return Status(Errc::not_found, quoted + "no models folder was given");
    }
    out = models_directory / (std::string(name) + ".off");
    std::error_code ec;
    if (!std::filesystem::is_regular_file(out, ec)) {
        return Status(Errc::not_found,
                      quoted + out.string() + " is not there (run tools/fetch-models)");
    }
    return Status::ok();
}

}  // namespace dfm::mesh
