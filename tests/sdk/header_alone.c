/* The public header alone, as a C translation unit sees it: nothing of C++
 * may leak in, and the descriptors must zero-initialise with {0}. */
#include "dualform/dualform.h"

/* C's zero-initialiser; C++ (where the header must compile too) spells it {}. */
#ifdef __cplusplus
#define ZERO \
    {}
#else
#define ZERO \
    { 0 }
#endif

int dfm_header_alone_check(void);

int dfm_header_alone_check(void) {
    dfm_context_desc context = ZERO;
    dfm_mesh_desc mesh = ZERO;
    dfm_session_desc session = ZERO;
    dfm_solver_settings solver = ZERO;
    dfm_frame_info frame = ZERO;
    dfm_camera camera = ZERO;
    return (int)context.worker_count + (int)mesh.triangle_count + (int)session.group_count +
           (int)solver.max_iterations + (int)frame.iterations + (int)camera.width +
           (DFM_VERSION > 0 ? 0 : 1);
}
