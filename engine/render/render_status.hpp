#pragma once

#include <string>
#include <utility>

#include <vulkan/vulkan.h>

namespace dfm::render {

// What went wrong in the renderer; maps one-to-one onto the C API's codes.
enum class Fault { none, invalid_argument, unsupported, io_error, out_of_memory, device };

// The outcome of a fallible renderer call: engine Status has no notion of a
// failing device, so the renderer carries its own.
class RenderStatus {
public:
    RenderStatus() = default;
    RenderStatus(Fault fault, std::string message) : fault_(fault), message_(std::move(message)) {}

    static RenderStatus ok() { return {}; }

    bool is_ok() const { return fault_ == Fault::none; }
    explicit operator bool() const { return is_ok(); }
    Fault fault() const { return fault_; }
    const std::string& message() const { return message_; }

private:
    Fault fault_ = Fault::none;
    std::string message_;
};

// A failed Vulkan call as a status naming the call and the VkResult; running
// out of host or device memory is reported as such, anything else as a
// device failure.
RenderStatus vk_failure(VkResult result, const char* call);

const char* vk_result_name(VkResult result);

}  // namespace dfm::render
