// Pieces that more than one file of C entry points needs: a new mesh handle,
// a file loaded into one, and a frame's public info.
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

// dfm_mesh_load's work for `function`: resolves model:NAME through the
// context's models folder, loads, logs the loader's warnings and fills
// `load_report`.
dfm_result load_mesh_file(const char* function, ContextObject& context, const char* path,
                          mesh::LoadReport& load_report, dfm_mesh** out);

// The public info of a published frame; nothing when `out` is NULL.
void fill_frame_info(const deform::Frame& frame, dfm_frame_info* out);

}  // namespace dfm::sdk
