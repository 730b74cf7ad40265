#include "handle_table.hpp"

#include <new>

namespace dfm::sdk {

namespace {

// Bits 0-27: slot index + 1 (never zero, so no handle is NULL); 28-31: the
// kind + 1; 32-63: the slot's generation.
constexpr std::uint64_t index_mask = (1u << 28) - 1;

std::uint64_t encode(Kind kind, std::uint32_t index, std::uint32_t generation) {
    return (std::uint64_t{generation} << 32) |
           (std::uint64_t{static_cast<std::uint8_t>(kind) + 1u} << 28) | (index + 1u);
}

}  // namespace

HandleTable::Slot* HandleTable::slot(std::uint32_t index) const noexcept {
    const std::size_t page = index / page_size;
    if (page >= max_pages) return nullptr;
    Slot* slots = pages_[page].load(std::memory_order_acquire);
    return slots == nullptr ? nullptr : &slots[index % page_size];
}

HandleTable::Slot& HandleTable::made_slot(std::uint32_t index) const noexcept {
    return pages_[index / page_size].load(std::memory_order_relaxed)[index % page_size];
}

std::uint64_t HandleTable::insert(void* object) {
    std::lock_guard<std::mutex> lock(mutex_);
    std::uint32_t index = 0;
    if (free_head_ != none) {
        index = free_head_;
        free_head_ = made_slot(index).next_free;
        if (free_head_ == none) free_tail_ = none;
    } else {
        if (used_ == page_size * max_pages) throw std::bad_alloc();
        index = used_;
        if (index % page_size == 0) {
            pages_[index / page_size].store(new Slot[page_size], std::memory_order_release);
        }
        ++used_;
    }
    Slot& s = made_slot(index);
    s.object.store(object, std::memory_order_release);
    return encode(kind_, index, s.generation.load(std::memory_order_relaxed));
}

void* HandleTable::find(std::uint64_t handle) const noexcept {
    const std::uint64_t low = handle & index_mask;
    if (low == 0 || ((handle >> 28) & 0xF) != static_cast<std::uint8_t>(kind_) + 1u) {
        return nullptr;
    }
    const Slot* s = slot(static_cast<std::uint32_t>(low - 1));
    if (s == nullptr) return nullptr;
    if (s->generation.load(std::memory_order_acquire) != static_cast<std::uint32_t>(handle >> 32)) {
        return nullptr;
    }
    return s->object.load(std::memory_order_acquire);
}

void* HandleTable::erase(std::uint64_t handle) noexcept {
    std::lock_guard<std::mutex> lock(mutex_);
    void* object = find(handle);
    if (object == nullptr) return nullptr;
    const auto index = static_cast<std::uint32_t>((handle & index_mask) - 1);
    Slot& s = made_slot(index);
    s.generation.fetch_add(1, std::memory_order_acq_rel);
    s.object.store(nullptr, std::memory_order_release);
    s.next_free = none;
    if (free_tail_ == none) {
        free_head_ = index;
    } else {
        made_slot(free_tail_).next_free = index;
    }
    free_tail_ = index;
    return object;
}

HandleTable& handles(Kind kind) {
    static HandleTable* const tables[] = {new HandleTable(Kind::context),
                                          new HandleTable(Kind::mesh), new HandleTable(Kind::roi),
                                          new HandleTable(Kind::session)};
    return *tables[static_cast<std::uint8_t>(kind)];
}

}  // namespace dfm::sdk
