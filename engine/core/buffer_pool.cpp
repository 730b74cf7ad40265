#include "core/buffer_pool.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cstdint>
#include <mutex>
#include <new>

#if defined(__linux__)
#include <sys/mman.h>
#include <unistd.h>
#endif

namespace dfm::buffer_pool {

namespace {

struct Block {
    void* memory = nullptr;
    std::size_t capacity = 0;
};

// Fixed tables, so that neither allocate's bookkeeping nor deallocate ever
// allocates. A block beyond the live table's room is not tracked: it is
// made for its request alone and freed when it comes back.
constexpr std::size_t live_room = 1024;
constexpr std::size_t kept_room = 256;

bool is_huge(std::size_t capacity) {
    return capacity >= huge_bytes;
}

// Blocks come in size classes, eight to each doubling (a block is at most
// an eighth larger than its request), and a request takes a kept block of
// its own class only. Sizes that close are interchangeable, so a set-up
// like the one before finds a block for every request; a looser fit let
// one array take a block that a later, larger one needed, and each such
// miss pushed out another kept block. From 32 MiB the classes are whole
// huge pages.
std::size_t capacity_for(std::size_t bytes) {
    const std::size_t step = std::max(std::bit_floor(bytes) / 8, std::size_t{4096});
    return (bytes + step - 1) / step * step;
}

std::align_val_t alignment_of(std::size_t capacity) {
    return std::align_val_t{is_huge(capacity) ? huge_page : max_alignment};
}

void free_block(const Block& block) noexcept {
    ::operator delete(block.memory, alignment_of(block.capacity));
}

struct Pool {
    std::mutex mutex;
    std::size_t holders = 0;
    std::array<Block, live_room> live{};
    std::size_t live_count = 0;
    std::array<Block, kept_room> kept{};
    std::size_t kept_count = 0;
    Counts counts;

    void remove_kept(std::size_t i) {
        counts.kept_bytes -= kept[i].capacity;
        kept[i] = kept[--kept_count];
    }

    std::size_t find_kept(std::size_t capacity) const {
        for (std::size_t i = 0; i < kept_count; ++i) {
            if (kept[i].capacity == capacity) return i;
        }
        return kept_count;
    }

    // Frees kept blocks until `capacity` more fits within a quarter above
    // the peak of the bytes in use: the smallest block that makes room
    // alone, or else the largest and again, so that as few bytes as may be
    // come back fresh. The quarter is room for a set-up's early temporaries
    // beside the blocks its later arrays will want: under the peak itself
    // they are of different classes and cannot all stay, and each miss
    // pushed out a block that a later request needed.
    void make_room(std::size_t capacity) {
        const std::size_t peak = std::max(counts.peak_in_use_bytes, counts.in_use_bytes + capacity);
        const std::size_t limit = peak + peak / 4;
        while (kept_count > 0 && counts.in_use_bytes + counts.kept_bytes + capacity > limit) {
            const std::size_t excess = counts.in_use_bytes + counts.kept_bytes + capacity - limit;
            std::size_t pick = kept_count;
            std::size_t largest = 0;
            for (std::size_t i = 0; i < kept_count; ++i) {
                const std::size_t c = kept[i].capacity;
                if (c >= excess && (pick == kept_count || c < kept[pick].capacity)) pick = i;
                if (c > kept[largest].capacity) largest = i;
            }
            if (pick == kept_count) pick = largest;
            free_block(kept[pick]);
            remove_kept(pick);
        }
    }

    void free_kept() {
        while (kept_count > 0) {
            free_block(kept[kept_count - 1]);
            remove_kept(kept_count - 1);
        }
    }

    void add_live(const Block& block) {
        counts.in_use_bytes += block.capacity;
        counts.peak_in_use_bytes = std::max(counts.peak_in_use_bytes, counts.in_use_bytes);
        live[live_count++] = block;
    }
};

// Built in static storage and never destroyed: a buffer freed by another
// static object's destructor at exit still finds it, and it is no
// allocation of its own for a host (or a leak check) to count.
Pool& pool() {
    alignas(Pool) static unsigned char storage[sizeof(Pool)];
    static Pool* const instance = new (storage) Pool;
    return *instance;
}

void* fresh_block(std::size_t capacity) {
    void* memory = ::operator new(capacity, alignment_of(capacity));
#if defined(__linux__) && defined(MADV_HUGEPAGE)
    // Advice only: where the kernel declines, the pages stay small.
    if (is_huge(capacity)) (void)::madvise(memory, capacity, MADV_HUGEPAGE);
#endif
    return memory;
}

// The pages a fresh block's request covers, made present in one call: on a
// virtual machine each first touch of a page is a costly fault, and one
// call that populates them all costs far less than faulting them one by
// one as they are written. Outside the pool's lock, which other threads'
// requests wait on. Only the request's pages: a block's class may be an
// eighth larger, and that tail may never be used. Advice only: a kernel
// without MADV_POPULATE_WRITE (before Linux 5.14) leaves the pages to
// fault one by one.
void populate(void* memory, std::size_t bytes) noexcept {
#if defined(__linux__) && defined(MADV_POPULATE_WRITE)
    static const auto page = static_cast<std::uintptr_t>(::sysconf(_SC_PAGESIZE));
    const auto first = reinterpret_cast<std::uintptr_t>(memory);
    const std::uintptr_t begin = (first + page - 1) / page * page;
    const std::uintptr_t end = (first + bytes) / page * page;
    if (end > begin)
        (void)::madvise(reinterpret_cast<void*>(begin), end - begin, MADV_POPULATE_WRITE);
#else
    (void)memory;
    (void)bytes;
#endif
}

}  // namespace

void* allocate(std::size_t bytes, std::size_t alignment) {
    if (alignment > max_alignment) throw std::bad_alloc();
    const std::size_t capacity = capacity_for(bytes);
    Pool& p = pool();
    void* memory = nullptr;
    {
        std::lock_guard<std::mutex> lock(p.mutex);
        if (p.live_count == live_room) {
            // Untracked: freed when it comes back, by the size it was asked for.
            p.counts.in_use_bytes += capacity;
            ++p.counts.fresh;
            memory = fresh_block(capacity);
        } else if (const std::size_t i = p.find_kept(capacity); i < p.kept_count) {
            const Block block = p.kept[i];
            p.remove_kept(i);
            p.add_live(block);
            ++p.counts.reused;
            return block.memory;
        } else {
            p.make_room(capacity);
            const Block block{fresh_block(capacity), capacity};
            p.add_live(block);
            ++p.counts.fresh;
            memory = block.memory;
        }
    }
    populate(memory, bytes);
    return memory;
}

void deallocate(void* memory, std::size_t bytes) noexcept {
    if (memory == nullptr) return;
    Pool& p = pool();
    std::lock_guard<std::mutex> lock(p.mutex);
    Block block{memory, capacity_for(bytes)};
    for (std::size_t i = 0; i < p.live_count; ++i) {
        if (p.live[i].memory == memory) {
            block = p.live[i];
            p.live[i] = p.live[--p.live_count];
            break;
        }
    }
    p.counts.in_use_bytes -= std::min(p.counts.in_use_bytes, block.capacity);
    if (p.holders == 0 || p.kept_count == kept_room) {
        free_block(block);
        return;
    }
    p.kept[p.kept_count++] = block;
    p.counts.kept_bytes += block.capacity;
}

void hold() noexcept {
    Pool& p = pool();
    std::lock_guard<std::mutex> lock(p.mutex);
    ++p.holders;
}

void release() noexcept {
    Pool& p = pool();
    std::lock_guard<std::mutex> lock(p.mutex);
    if (--p.holders == 0) p.free_kept();
}

Counts counts() noexcept {
    Pool& p = pool();
    std::lock_guard<std::mutex> lock(p.mutex);
    return p.counts;
}

}  // namespace dfm::buffer_pool
