#pragma once

#include <string>
#include <utility>

namespace dfm {

// Error categories that map one-to-one onto the C API's result codes.
enum class Errc {
    ok = 0,
    invalid_argument,
    not_found,
    io_error,
    parse_error,
    out_of_range,
    unsupported,
    out_of_memory,
    numerical,
    internal,   // a defect of Dualform's, not of the caller's input
    cancelled,  // stopped by the caller's stop flag before it finished
    device,     // the graphics device failed (the renderer only)
    busy,       // the object is in use in a way that forbids the call
};

const char* errc_name(Errc code);

// The outcome of a fallible engine call, the renderer's included. The message
// names what was wrong and where (file, line or byte offset, element, Vulkan
// call), ready to show to a user.
class Status {
public:
    Status() = default;
    Status(Errc code, std::string message) : code_(code), message_(std::move(message)) {}

    static Status ok() { return {}; }

    bool is_ok() const { return code_ == Errc::ok; }
    explicit operator bool() const { return is_ok(); }
    Errc code() const { return code_; }
    const std::string& message() const { return message_; }

private:
    Errc code_ = Errc::ok;
    std::string message_;
};

}  // namespace dfm
