#pragma once

#include "c_boundary.hpp"
#include "render/render_status.hpp"

namespace dfm::sdk {

// Records a failing renderer status under the C function's name; ok passes.
dfm_result report_render(const char* function, const render::RenderStatus& status);

}  // namespace dfm::sdk
