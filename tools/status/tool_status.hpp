#pragma once

#include <string>
#include <utility>

#include "dualform/dualform.h"

namespace dfm {

// The outcome of a fallible step of the tools (the dualform tool and the
// JSON reader), in the C API's own terms: a dfm_result code
// (DFM_ERROR_IO for a file a tool could not read, DFM_ERROR_PARSE for a
// malformed document) and a message that names what was wrong and where,
// ready to print after "error: ". The engine's own status is dfm::Status;
// the tools see the library only through dualform.h.
class ToolStatus {
public:
    ToolStatus() = default;
    ToolStatus(dfm_result code, std::string message) : code_(code), message_(std::move(message)) {}

    static ToolStatus ok() { return {}; }

    bool is_ok() const { return code_ == DFM_OK; }
    explicit operator bool() const { return is_ok(); }
    dfm_result code() const { return code_; }
    const std::string& message() const { return message_; }

private:
    dfm_result code_ = DFM_OK;
    std::string message_;
};

}  // namespace dfm
