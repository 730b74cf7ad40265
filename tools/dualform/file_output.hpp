#pragma once

#include <cstdint>
#include <span>
#include <string>

#include "status/tool_status.hpp"

namespace dfm::cli {

// Writes `text` and a final line break to `path`, replacing the file.
ToolStatus write_text_file(const std::string& path, const std::string& text);

// Writes one number a line.
ToolStatus write_index_lines(const std::string& path, std::span<const std::uint32_t> values);

}  // namespace dfm::cli
