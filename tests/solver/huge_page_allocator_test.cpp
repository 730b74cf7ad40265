#include <doctest/doctest.h>

#include <cstddef>
#include <cstdint>
#include <fstream>
#include <sstream>
#include <string>

#include "core/huge_page_allocator.hpp"

using namespace dfm;

namespace {

// The VmFlags line of the mapping that holds `address` (Linux's smaps), or
// "" where there is none.
std::string mapping_flags(const void* address) {
    std::ifstream smaps("/proc/self/smaps");
    const auto at = reinterpret_cast<std::uintptr_t>(address);
    std::string line;
    bool inside = false;
    while (std::getline(smaps, line)) {
        std::uintptr_t begin = 0, end = 0;
        char dash = 0;
        std::istringstream head(line);
        if (head >> std::hex >> begin >> dash >> end && dash == '-') {
            inside = begin <= at && at < end;
        } else if (inside && line.rfind("VmFlags:", 0) == 0) {
            return line;
        }
    }
    return "";
}

}  // namespace

TEST_CASE("huge pages: a buffer of 32 MiB or more is aligned to 2 MiB and advised as huge pages") {
    constexpr std::size_t huge_page = std::size_t{2} << 20;
    HugePageVector<double> big((std::size_t{32} << 20) / sizeof(double) + 3, 1.5);
    CHECK(reinterpret_cast<std::uintptr_t>(big.data()) % huge_page == 0);
    CHECK(big.back() == 1.5);
#if defined(__linux__) && defined(MADV_HUGEPAGE)
    std::ifstream enabled("/sys/kernel/mm/transparent_hugepage/enabled");
    std::string modes;
    std::getline(enabled, modes);
    if (modes.find("[never]") == std::string::npos && !modes.empty()) {
        const std::string flags = mapping_flags(big.data());
        INFO(flags);
        CHECK(flags.find(" hg") != std::string::npos);
    }
#endif
    // Growth moves the values into a new buffer of the same kind.
    big.push_back(2.5);
    CHECK(reinterpret_cast<std::uintptr_t>(big.data()) % huge_page == 0);
    CHECK(big[0] == 1.5);
    CHECK(big.back() == 2.5);
}

TEST_CASE("huge pages: a smaller buffer is ordinary memory") {
    HugePageVector<std::uint32_t> small(1000, 7u);
    CHECK(reinterpret_cast<std::uintptr_t>(small.data()) % alignof(std::max_align_t) == 0);
    CHECK(small[999] == 7u);
    HugePageVector<std::uint32_t> copy = small;
    CHECK(copy == small);
}
