#pragma once

#include <cstddef>

#include <doctest/doctest.h>

// Checks that `field` of a frozen copy of a struct's layout lies where the
// struct of today has it, at the same size (the struct_size tables' tests).
#define CHECK_SAME_PLACE(layout, desc, field)                                \
    CHECK_MESSAGE(offsetof(layout, field) == offsetof(desc, field), #field); \
    CHECK_MESSAGE(sizeof(layout::field) == sizeof(desc::field), #field)
