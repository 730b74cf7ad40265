// Pieces that more than one file of C entry points needs: a new mesh handle
// and a frame's public info.
#pragma once

#include "deform/async_session.hpp"
#include "dualform/dualform.h"
#include "mesh/host_mesh.hpp"
#include "mesh/load.hpp"
#include "objects.hpp"

namespace dfm::sdk {

// A mesh handle over `mesh` (the surface), its model and state in the
// context's memory; `host` keeps the host's numbering and any glTF asset.
dfm_result make_mesh_handle(const ContextState& context,
                            const std::shared_ptr<const ContextState>& shared, mesh::Mesh mesh,
                            dfm_mesh** out, mesh::HostMesh host = {});

// The public info of a published frame; nothing when `out` is NULL.
void fill_frame_info(const deform::Frame& frame, dfm_frame_info* out);

// After a step of the mesh's history in a pose (a bake, new positions):
// DFM_LOG_ID_CORRECTIVE_DAMPED naming the vertices, in the host's numbering,
// whose corrective took the damped inverse, if any did. `fn` names the call.
void log_damped_corrective(const MeshState& mesh, const char* fn);

}  // namespace dfm::sdk
