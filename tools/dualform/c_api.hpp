#pragma once

#include <cstdint>
#include <memory>
#include <string>

#include "dualform/dualform.h"
#include "status/tool_status.hpp"

// The tool's side of the C API: owning pointers for its handles, and its
// failures as the tool's statuses.
namespace dfm::cli {

template <class T, void (*destroy)(T*)>
struct HandleDeleter {
    void operator()(T* handle) const { destroy(handle); }
};

using ContextPtr = std::unique_ptr<dfm_context, HandleDeleter<dfm_context, dfm_context_destroy>>;
using MeshPtr = std::unique_ptr<dfm_mesh, HandleDeleter<dfm_mesh, dfm_mesh_destroy>>;
using RoiPtr = std::unique_ptr<dfm_roi, HandleDeleter<dfm_roi, dfm_roi_destroy>>;
using SessionPtr = std::unique_ptr<dfm_session, HandleDeleter<dfm_session, dfm_session_destroy>>;

// DFM_OK, or the last failure's message (which names the call) prefixed by
// `what` when that is not empty ("roi: dfm_roi_ball: ...").
ToolStatus api_status(dfm_result result, const std::string& what = {});

// A context configured from the tool's environment (the models folder of
// model:NAME), with load warnings printed on stderr as "warning: ...", whose
// sessions solve with `worker_count` threads.
ToolStatus create_context(ContextPtr& out, std::uint32_t worker_count = 1);

}  // namespace dfm::cli
