#include "support/test_files.hpp"

#include <fstream>
#include <sstream>
#include <stdexcept>

namespace dfm::test {

std::filesystem::path data_dir() {
    return DUALFORM_TEST_DATA_DIR;
}

std::filesystem::path scratch_dir(std::string_view name) {
    const std::filesystem::path dir =
        std::filesystem::path(DUALFORM_TEST_SCRATCH_DIR) / std::string(name);
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    return dir;
}

void write_text(const std::filesystem::path& path, std::string_view text) {
    std::ofstream out(path, std::ios::binary);
    out.write(text.data(), static_cast<std::streamsize>(text.size()));
    if (!out) throw std::runtime_error("cannot write " + path.string());
}

std::string read_text(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw std::runtime_error("cannot read " + path.string());
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

}  // namespace dfm::test
