#define DOCTEST_CONFIG_IMPLEMENT
#include <doctest/doctest.h>

#include "support/test_run.hpp"

int main(int argc, char** argv) {
    return run_test_cases(argc, argv);
}
