#include <mutex>
#include <unordered_map>

#include "objects.hpp"

namespace dfm::sdk {

namespace {

struct Registry {
    std::mutex mutex;
    std::unordered_map<const void*, Kind> live;
};

Registry& registry() {
    // Never destroyed: hosts may destroy handles from static destructors.
    static Registry* instance = new Registry;
    return *instance;
}

}  // namespace

void register_handle(const void* handle, Kind kind) {
    Registry& r = registry();
    std::lock_guard<std::mutex> lock(r.mutex);
    r.live.emplace(handle, kind);
}

void unregister_handle(const void* handle) {
    Registry& r = registry();
    std::lock_guard<std::mutex> lock(r.mutex);
    r.live.erase(handle);
}

bool is_live(const void* handle, Kind kind) {
    if (handle == nullptr) return false;
    Registry& r = registry();
    std::lock_guard<std::mutex> lock(r.mutex);
    const auto it = r.live.find(handle);
    return it != r.live.end() && it->second == kind;
}

}  // namespace dfm::sdk
