#include "mesh/model_cache.hpp"

#include <pwd.h>
#include <unistd.h>

#include <cstdlib>
#include <string>

namespace dfm::mesh {

std::filesystem::path models_directory() {
    if (const char* dir = std::getenv("DUALFORM_MODELS"); dir != nullptr && *dir != '\0') {
        return dir;
    }
    const char* home = std::getenv("HOME");
    if (home == nullptr || *home == '\0') {
        const passwd* user = getpwuid(getuid());
        home = user != nullptr ? user->pw_dir : "/tmp";
    }
    return std::filesystem::path(home) / ".cache" / "dualform" / "models";
}

Status resolve_mesh_spec(std::string_view spec, const std::filesystem::path& base,
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
    out = models_directory() / (std::string(name) + ".off");
    std::error_code ec;
    if (!std::filesystem::is_regular_file(out, ec)) {
        return Status(Errc::not_found,
                      quoted + out.string() + " is not there (run tools/fetch-models)");
    }
    return Status::ok();
}

}  // namespace dfm::mesh
