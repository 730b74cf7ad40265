#pragma once

// What struct_size 0 stands for in each struct of dualform.h that begins
// with struct_size: the size of its layout in version 0.2, where
// struct_size appeared, which is every field the 0.2.0 header declares.
// A later version that adds fields leaves these entries as they are: a
// host that passes 0 was built against the 0.2 layout or zeroed a newer
// struct without setting the field, and the newer fields take their
// defaults. tests/sdk/descriptor_test.cpp checks each entry against a copy
// of its 0.2 layout.

#include <cstddef>

#include "dualform/dualform.h"

// The end of a struct's member: the struct_size of a layout that ended there.
#define DFM_END_OF(type, member) (offsetof(type, member) + sizeof(((type*)nullptr)->member))

namespace dfm::sdk {

// Declared for each struct that begins with struct_size, and only for
// those: reading one the table lacks does not compile.
template <class Desc>
struct FirstLayout;

}  // namespace dfm::sdk

// The table's entry for `type`, whose first layout ends at `last`.
#define DFM_FIRST_LAYOUT(type, last)                                \
    template <>                                                     \
    struct dfm::sdk::FirstLayout<type> {                            \
        static constexpr std::size_t size = DFM_END_OF(type, last); \
    }

DFM_FIRST_LAYOUT(dfm_context_desc, job_system);
DFM_FIRST_LAYOUT(dfm_mesh_desc, skin);
DFM_FIRST_LAYOUT(dfm_session_desc, on_frame_user);
DFM_FIRST_LAYOUT(dfm_vertex_output, changed_only);
DFM_FIRST_LAYOUT(dfm_solve_details, predicted);
DFM_FIRST_LAYOUT(dfm_save_options, morph_target_name);
