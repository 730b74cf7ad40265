#pragma once

// The C API's handles are not addresses: each is the index of a slot in a
// table of its kind and the slot's generation when the object was created.
// Destroying an object bumps its slot's generation, so the old handle is
// refused for ever after, even when the host's allocator hands the same
// memory to the next object. Looking a handle up takes no lock.

#include <array>
#include <atomic>
#include <cstdint>
#include <mutex>

namespace dfm::sdk {

enum class Kind : std::uint8_t { context, mesh, roi, session };

class HandleTable {
public:
    explicit HandleTable(Kind kind) : kind_(kind) {}
    HandleTable(const HandleTable&) = delete;
    HandleTable& operator=(const HandleTable&) = delete;

    // A new handle for `object` (not null). Throws std::bad_alloc when the
    // table cannot grow.
    std::uint64_t insert(void* object);
    // The object of a live handle of this kind, or null. Lock-free.
    void* find(std::uint64_t handle) const noexcept;
    // Retires the handle and returns its object; null when it was not live.
    void* erase(std::uint64_t handle) noexcept;

private:
    static constexpr std::uint32_t none = 0xFFFFFFFFu;
    struct Slot {
        std::atomic<std::uint32_t> generation{1};
        std::atomic<void*> object{nullptr};
        std::uint32_t next_free = none;  // under mutex_
    };
    static constexpr std::size_t page_size = 1024;
    static constexpr std::size_t max_pages = 1u << 14;  // 16M live objects per kind

    // The slot of an index a handle names: null when it was never made.
    Slot* slot(std::uint32_t index) const noexcept;
    // The slot of an index the table has made (under mutex_).
    Slot& made_slot(std::uint32_t index) const noexcept;

    Kind kind_;
    std::array<std::atomic<Slot*>, max_pages> pages_{};
    std::mutex mutex_;  // creation and destruction only
    std::uint32_t used_ = 0;
    // Freed slots, oldest first, so a slot comes back as late as possible;
    // linked through the slots, so destroying never allocates.
    std::uint32_t free_head_ = none;
    std::uint32_t free_tail_ = none;
};

// The table of each kind. Never destroyed: hosts may destroy handles from
// static destructors.
HandleTable& handles(Kind kind);

}  // namespace dfm::sdk
