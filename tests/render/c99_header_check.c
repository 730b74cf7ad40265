/* dualform_vulkan.h must compile as C99 with -pedantic -Werror; the sizes
 * seen from C are handed to the C++ test so the two languages agree on them. */
#include "dualform/dualform_vulkan.h"

size_t dfm_vk_c99_struct_size(int which);

size_t dfm_vk_c99_struct_size(int which) {
    switch (which) {
        case 0: return sizeof(dfm_vec3_input);
        case 1: return sizeof(dfm_vk_polyline);
        case 2: return sizeof(dfm_vk_frame);
        case 3: return sizeof(dfm_vk_renderer_desc);
        case 4: return sizeof(dfm_vk_host_desc);
        default: return 0;
    }
}
