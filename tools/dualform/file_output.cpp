#include "dualform/file_output.hpp"

#include <fstream>

namespace dfm::cli {

ToolStatus write_text_file(const std::string& path, const std::string& text) {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out << text << '\n';
    out.close();
    if (!out) return ToolStatus(DFM_ERROR_IO, path + ": cannot write");
    return ToolStatus::ok();
}

ToolStatus write_index_lines(const std::string& path, std::span<const std::uint32_t> values) {
    std::string text;
    for (std::uint32_t v : values) {
        if (!text.empty()) text += '\n';
        text += std::to_string(v);
    }
    return write_text_file(path, text);
}

}  // namespace dfm::cli
