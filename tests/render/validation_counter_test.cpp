#include <doctest/doctest.h>

#include "render/device.hpp"
#include "render/instance.hpp"
#include "render/validation.hpp"

using namespace dfm::render;

// The other tests assert zero validation messages; this one shows that a
// message would be counted, so those assertions can fail.
TEST_CASE("render: the validation counter counts a misuse of Vulkan") {
    ValidationCounter counter;
    Instance instance;
    const dfm::Status created = Instance::create({}, true, counter, instance);
    REQUIRE_MESSAGE(created.is_ok(), created.message());
    Device device;
    REQUIRE(Device::create(instance.handle(), VK_NULL_HANDLE, device).is_ok());
    CHECK(counter.count() == 0);

    VkBufferCreateInfo info{};
    info.sType = VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO;
    info.size = 0;  // VUID-VkBufferCreateInfo-size-00912: size must be positive
    info.usage = VK_BUFFER_USAGE_VERTEX_BUFFER_BIT;
    VkBuffer buffer = VK_NULL_HANDLE;
    MESSAGE("a validation error is expected below");
    const VkResult result = vkCreateBuffer(device.gpu().device, &info, nullptr, &buffer);
    if (result == VK_SUCCESS && buffer != VK_NULL_HANDLE) {
        vkDestroyBuffer(device.gpu().device, buffer, nullptr);
    }
    CHECK(counter.count() > 0);
}
