#pragma once

#include <filesystem>
#include <string>
#include <string_view>

namespace dfm::test {

// tests/data in the source tree.
std::filesystem::path data_dir();

// A fresh, empty directory for one test's files, removed by the next run.
std::filesystem::path scratch_dir(std::string_view name);

void write_text(const std::filesystem::path& path, std::string_view text);
std::string read_text(const std::filesystem::path& path);

}  // namespace dfm::test
