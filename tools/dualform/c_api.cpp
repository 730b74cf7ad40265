#include "dualform/c_api.hpp"

#include <cstdio>

#include "environment/host_environment.hpp"

namespace dfm::cli {

namespace {

void print_warning(void*, dfm_log_level level, dfm_log_id id, const char* message) {
    if (level >= DFM_LOG_WARNING && id == DFM_LOG_ID_LOAD_WARNING) {
        std::fprintf(stderr, "warning: %s\n", message);
    }
}

}  // namespace

ToolStatus api_status(dfm_result result, const std::string& what) {
    if (result == DFM_OK) return ToolStatus::ok();
    std::string message = what;
    if (!message.empty()) message += ": ";
    message += dfm_last_error_message();
    return ToolStatus(result, std::move(message));
}

ToolStatus create_context(ContextPtr& out, std::uint32_t worker_count) {
    const std::string models = tools::models_folder_from_environment().string();
    dfm_context_desc desc = {};
    desc.models_directory = models.c_str();
    desc.log = print_warning;
    desc.worker_count = worker_count;
    dfm_context* context = nullptr;
    if (ToolStatus s = api_status(dfm_context_create(&desc, &context)); !s) return s;
    out.reset(context);
    return ToolStatus::ok();
}

}  // namespace dfm::cli
