// The renderer tests' main: pins the Vulkan loader to lavapipe (when the
// build found its ICD and the environment names no driver), so results do
// not depend on the machine's GPU. doctest_discover_tests cannot pass more
// than one ENVIRONMENT entry, hence here rather than in CTest.
#define DOCTEST_CONFIG_IMPLEMENT
#include <doctest/doctest.h>

#include <cstdlib>

#include "support/test_run.hpp"

int main(int argc, char** argv) {
#ifdef DUALFORM_LAVAPIPE_ICD
    if (std::getenv("VK_DRIVER_FILES") == nullptr && std::getenv("VK_ICD_FILENAMES") == nullptr) {
        setenv("VK_DRIVER_FILES", DUALFORM_LAVAPIPE_ICD, 0);
        setenv("VK_ICD_FILENAMES", DUALFORM_LAVAPIPE_ICD, 0);
    }
#endif
    return run_test_cases(argc, argv);
}
