#include "sdk/thread_creation.hpp"

#include <dlfcn.h>
#include <pthread.h>

#include <atomic>
#include <cstring>

namespace {

std::atomic<std::size_t> created{0};

using Create = int (*)(pthread_t*, const pthread_attr_t*, void* (*)(void*), void*);

Create real_create() {
    void* symbol = dlsym(RTLD_NEXT, "pthread_create");
    Create create = nullptr;
    std::memcpy(&create, &symbol, sizeof create);
    return create;
}

}  // namespace

extern "C" int pthread_create(pthread_t* thread, const pthread_attr_t* attributes,
                              void* (*start)(void*), void* argument) noexcept {
    static const Create real = real_create();
    created.fetch_add(1);
    return real(thread, attributes, start, argument);
}

namespace dfm::test {

std::size_t threads_created() {
    return created.load();
}

}  // namespace dfm::test
