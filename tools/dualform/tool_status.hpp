#pragma once

#include <string>
#include <utility>

#include "dualform/dualform.h"

namespace dfm::cli {

// The outcome of a fallible step of the tool, in the C API's own terms: a
// dfm_result code (DFM_ERROR_IO for a file the tool could not read) and a
// message that names what was wrong and where, ready to print after "error: ".
class Status {
public:
    Status() = default;
    Status(dfm_result code, std::string message) : code_(code), message_(std::move(message)) {}

    static Status ok() { return {}; }

    bool is_ok() const { return code_ == DFM_OK; }
    explicit operator bool() const { return is_ok(); }
    dfm_result code() const { return code_; }
    const std::string& message() const { return message_; }

private:
    dfm_result code_ = DFM_OK;
    std::string message_;
};

}  // namespace dfm::cli
