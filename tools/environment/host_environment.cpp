#include "environment/host_environment.hpp"

#include <pwd.h>
#include <unistd.h>

#include <cstdlib>
#include <cstring>

namespace dfm::tools {

std::filesystem::path models_folder_from_environment() {
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

bool validation_from_environment() {
    const char* value = std::getenv("DUALFORM_VALIDATION");
    return value != nullptr && std::strcmp(value, "1") == 0;
}

}  // namespace dfm::tools
