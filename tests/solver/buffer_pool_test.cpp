#include <doctest/doctest.h>

#include <cstddef>
#include <cstdint>
#include <fstream>
#include <new>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#if defined(__linux__)
#include <sys/mman.h>
#include <unistd.h>
#endif

#include "core/buffer_pool.hpp"
#include "core/pooled_allocator.hpp"

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

TEST_CASE("buffer pool: a buffer of 32 MiB or more is aligned to 2 MiB and advised as huge pages") {
    constexpr std::size_t huge_page = std::size_t{2} << 20;
    PooledVector<double> big((std::size_t{32} << 20) / sizeof(double) + 3, 1.5);
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

#if defined(__linux__) && defined(MADV_POPULATE_WRITE)
TEST_CASE("buffer pool: a fresh buffer's pages are present before its first write") {
    // Above glibc's largest mmap threshold, so the block is a mapping of
    // its own that nothing has touched.
    const std::size_t bytes = std::size_t{40} << 20;
    void* memory = buffer_pool::allocate(bytes, alignof(double));
    const auto page = static_cast<std::uintptr_t>(::sysconf(_SC_PAGESIZE));
    const std::uintptr_t begin =
        (reinterpret_cast<std::uintptr_t>(memory) + page - 1) / page * page;
    const std::uintptr_t end = (reinterpret_cast<std::uintptr_t>(memory) + bytes) / page * page;
    std::vector<unsigned char> present((end - begin) / page);
    REQUIRE(::mincore(reinterpret_cast<void*>(begin), end - begin, present.data()) == 0);
    std::size_t missing = 0;
    for (const unsigned char p : present) missing += (p & 1u) == 0 ? 1 : 0;
    // A kernel before 5.14 refuses the advice; then the pages fault as
    // they are written, and there is nothing to check.
    void* probe = ::mmap(nullptr, page, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
    REQUIRE(probe != MAP_FAILED);
    const bool supported = ::madvise(probe, page, MADV_POPULATE_WRITE) == 0;
    ::munmap(probe, page);
    if (supported) CHECK(missing == 0);
    buffer_pool::deallocate(memory, bytes);
}
#endif

TEST_CASE("buffer pool: a buffer under its threshold is ordinary memory, never counted") {
    const buffer_pool::Counts before = buffer_pool::counts();
    PooledVector<std::uint32_t> small(1000, 7u);
    CHECK(reinterpret_cast<std::uintptr_t>(small.data()) % alignof(std::max_align_t) == 0);
    CHECK(small[999] == 7u);
    PooledVector<std::uint32_t> copy = small;
    CHECK(copy == small);
    const buffer_pool::Counts after = buffer_pool::counts();
    CHECK(after.fresh == before.fresh);
    CHECK(after.in_use_bytes == before.in_use_bytes);
}

TEST_CASE("buffer pool: without a holder a freed buffer goes back at once") {
    const buffer_pool::Counts before = buffer_pool::counts();
    REQUIRE(before.kept_bytes == 0);
    { PooledVector<double> a(std::size_t{1} << 18, 1.0); }
    const buffer_pool::Counts after = buffer_pool::counts();
    CHECK(after.kept_bytes == 0);
    CHECK(after.in_use_bytes == before.in_use_bytes);
    CHECK(after.fresh == before.fresh + 1);
}

TEST_CASE("buffer pool: while held, a freed buffer serves the next request of its size class") {
    const buffer_pool::Counts start = buffer_pool::counts();
    REQUIRE(start.kept_bytes == 0);
    {
        const buffer_pool::Hold hold;
        constexpr std::size_t n = std::size_t{1} << 18;  // 2 MiB of doubles
        const double* first = nullptr;
        {
            PooledVector<double> a(n, 1.0);
            first = a.data();
        }
        CHECK(buffer_pool::counts().kept_bytes == n * sizeof(double));
        {
            // A little smaller is the same class: the kept block, zeroed as asked.
            PooledVector<double> b(n - 1000);
            CHECK(b.data() == first);
            CHECK(b.front() == 0.0);
            CHECK(b.back() == 0.0);
            CHECK(buffer_pool::counts().kept_bytes == 0);
        }
        {
            // An eighth larger is the next class: a fresh block.
            PooledVector<double> c(n + n / 8);
            CHECK(c.data() != first);
        }
        {
            // So is half the size, which would waste the block.
            PooledVector<double> d(n / 2);
            CHECK(d.data() != first);
        }
        const buffer_pool::Counts held = buffer_pool::counts();
        CHECK(held.reused == start.reused + 1);
        CHECK(held.fresh == start.fresh + 3);
        CHECK(held.in_use_bytes == start.in_use_bytes);
        CHECK(held.kept_bytes >= n / 2 * sizeof(double));
        CHECK(held.in_use_bytes + held.kept_bytes <= held.peak_in_use_bytes);
    }
    // The last holder frees what was kept.
    CHECK(buffer_pool::counts().kept_bytes == 0);
}

TEST_CASE("buffer pool: kept and used together never exceed the peak in use") {
    const buffer_pool::Hold hold;
    const buffer_pool::Counts start = buffer_pool::counts();
    // Larger than any peak so far, so that this test sets the peak. Never
    // touched: operator new only reserves the addresses.
    const std::size_t size = start.peak_in_use_bytes + (std::size_t{8} << 20);
    void* a = buffer_pool::allocate(size, alignof(double));
    buffer_pool::deallocate(a, size);
    CHECK(buffer_pool::counts().kept_bytes == start.kept_bytes + size);
    // A larger request cannot use the kept block; keeping it too would pass
    // the peak, so it is freed first.
    const std::size_t larger = size + (std::size_t{4} << 20);
    void* b = buffer_pool::allocate(larger, alignof(double));
    const buffer_pool::Counts after = buffer_pool::counts();
    CHECK(after.kept_bytes == start.kept_bytes);
    CHECK(after.in_use_bytes + after.kept_bytes <= after.peak_in_use_bytes);
    buffer_pool::deallocate(b, larger);
}

TEST_CASE("buffer pool: threads allocate and free at once, and everything comes back") {
    const buffer_pool::Counts start = buffer_pool::counts();
    {
        const buffer_pool::Hold hold;
        auto churn = [](std::size_t base) {
            for (std::size_t i = 0; i < 200; ++i) {
                PooledVector<std::uint32_t> v(base + i / 2 % 7 * 8192,
                                              static_cast<std::uint32_t>(i));
                CHECK(v[v.size() / 2] == i);
            }
        };
        std::thread other(churn, std::size_t{1} << 16);
        churn(std::size_t{1} << 17);
        other.join();
        const buffer_pool::Counts held = buffer_pool::counts();
        CHECK(held.in_use_bytes == start.in_use_bytes);
        CHECK(held.reused > start.reused);
    }
    CHECK(buffer_pool::counts().kept_bytes == 0);
}

// The sanitizers' allocators end the process on an impossible size instead
// of throwing, so this one runs in the plain builds.
#if !defined(__SANITIZE_ADDRESS__) && !defined(__SANITIZE_THREAD__)
TEST_CASE("buffer pool: a failed allocation throws bad_alloc and leaves the pool as it was") {
    const buffer_pool::Hold hold;
    const buffer_pool::Counts start = buffer_pool::counts();
    CHECK_THROWS_AS(buffer_pool::allocate(std::size_t{1} << 62, alignof(double)), std::bad_alloc);
    const buffer_pool::Counts after = buffer_pool::counts();
    CHECK(after.in_use_bytes == start.in_use_bytes);
    CHECK(after.fresh == start.fresh);
    // The pool is not left locked.
    PooledVector<double> v(std::size_t{1} << 17, 3.0);
    CHECK(v.back() == 3.0);
}
#endif
