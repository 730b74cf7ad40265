#pragma once

#include <cstddef>

namespace dfm::test {

// Threads the process has created so far: the test executable defines
// pthread_create (thread_creation.cpp), which comes first in the dynamic
// lookup, so the library's, libstdc++'s and the tests' calls all pass
// through it on their way to the real one.
std::size_t threads_created();

}  // namespace dfm::test
