// Every C entry point runs inside one guard: an exception thrown anywhere in
// it, building an error message included, comes back as a result code.
// This executable replaces the global operator new so that a test can make
// allocations on its own thread throw during one call.
#include <doctest/doctest.h>

#include <cstdlib>
#include <new>
#include <stdexcept>
#include <string>

#include "dualform/dualform.h"
#include "sdk/sdk_fixture.hpp"

namespace {

enum class Injected { none, bad_alloc, other };
thread_local Injected injected = Injected::none;

// Runs `call` with allocations on this thread throwing `what`: every one
// for bad_alloc, the first one for another exception.
template <class Call>
dfm_result with_failing_new(Injected what, Call&& call) {
    injected = what;
    const dfm_result result = call();
    injected = Injected::none;
    return result;
}

}  // namespace

void* operator new(std::size_t size) {
    if (injected == Injected::bad_alloc) throw std::bad_alloc();
    if (injected == Injected::other) {
        injected = Injected::none;  // the exception's own message allocates
        throw std::runtime_error("injected failure");
    }
    if (void* memory = std::malloc(size != 0 ? size : 1)) return memory;
    throw std::bad_alloc();
}

void operator delete(void* memory) noexcept {
    std::free(memory);
}

void operator delete(void* memory, std::size_t) noexcept {
    std::free(memory);
}

using namespace dfm::test;

TEST_CASE("guard: an allocation failing while a message is built is out of memory, not a crash") {
    LimbEdit limb;
    double m[16];
    translation(0, 0, 0, m);
    // Each of these fails on bad input, so it builds a message.
    CHECK(with_failing_new(Injected::bad_alloc, [&] {
              return dfm_session_set_group_transform(limb.session, 999, m);
          }) == DFM_ERROR_OUT_OF_MEMORY);
    CHECK(std::string(dfm_last_error_message()) ==
          "dfm_session_set_group_transform: out of memory");
    CHECK(with_failing_new(Injected::bad_alloc, [&] {
              return dfm_session_wait(limb.session, 99, 0, nullptr);
          }) == DFM_ERROR_OUT_OF_MEMORY);
    std::size_t count = 0;
    CHECK(with_failing_new(Injected::bad_alloc, [&] {
              return dfm_roi_count(reinterpret_cast<const dfm_roi*>(limb.mesh), &count);
          }) == DFM_ERROR_OUT_OF_MEMORY);
    CHECK(with_failing_new(Injected::bad_alloc, [&] {
              dfm_context* context = nullptr;
              dfm_context_desc desc = {};
              desc.worker_count = 100000;
              return dfm_context_create(&desc, &context);
          }) == DFM_ERROR_OUT_OF_MEMORY);
    // The session is untouched and works.
    std::uint64_t g = 0;
    REQUIRE(dfm_session_submit(limb.session, &g) == DFM_OK);
    CHECK(dfm_session_wait(limb.session, g, -1, nullptr) == DFM_OK);
}

TEST_CASE("guard: any other exception is DFM_ERROR_INTERNAL with its text") {
    LimbEdit limb;
    double m[16];
    translation(0, 0, 0, m);
    CHECK(with_failing_new(Injected::other, [&] {
              return dfm_session_set_group_transform(limb.session, 999, m);
          }) == DFM_ERROR_INTERNAL);
    CHECK(std::string(dfm_last_error_message()) ==
          "dfm_session_set_group_transform: injected failure");
    CHECK(std::string(dfm_result_name(DFM_ERROR_INTERNAL)) == "DFM_ERROR_INTERNAL");
    dfm_roi* grown = nullptr;
    CHECK(with_failing_new(Injected::other, [&] { return dfm_roi_grow(limb.roi, 1, &grown); }) ==
          DFM_ERROR_INTERNAL);
    CHECK(grown == nullptr);
}
