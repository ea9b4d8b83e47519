// Vulkan backend of nrd::rhi: creates an rhi::Device over the application's VkDevice and converts
// between native Vulkan handles and rhi objects. The only rhi header that includes Vulkan.
#pragma once

#include "RHI.h"

#include <vulkan/vulkan.h>

namespace nrd
{
namespace rhi
{

struct DeviceVulkanDesc
{
    VkInstance instance = VK_NULL_HANDLE;             // (Optional) Only for debug names / labels.
    VkPhysicalDevice physicalDevice = VK_NULL_HANDLE;
    VkDevice device = VK_NULL_HANDLE;                 // Owned by the application; must outlive the rhi device.
    uint32_t queueFamilyIndex = 0;                    // Must support compute.
    // (Optional) Queue of 'queueFamilyIndex' for CreateCommandBuffer / SubmitAndWait / WaitIdle.
    // Without it those return UNSUPPORTED; recording into wrapped command buffers still works.
    VkQueue queue = VK_NULL_HANDLE;
    // The device was created with these features enabled (the rhi cannot query what was enabled).
    bool storageImageReadWithoutFormatEnabled = false;
    bool storageImageWriteWithoutFormatEnabled = false;
    const VkAllocationCallbacks* allocationCallbacks = nullptr; // (Optional)
};

// Creates a device over 'desc.device'. Destroy it with DestroyDevice before destroying the VkDevice.
Result CreateDeviceVulkan(const DeviceVulkanDesc& desc, Device*& out);

// Wraps an application image for descriptors and barriers (not copies if the format is UNKNOWN).
// 'view' is a 2D, single-mip, color view. The wrapper owns nothing; destroy it with
// Device::DestroyTexture before (or after) the image itself is destroyed.
struct TextureVulkanDesc
{
    VkImage image = VK_NULL_HANDLE;
    VkImageView view = VK_NULL_HANDLE;
    VkFormat format = VK_FORMAT_UNDEFINED;
    uint32_t width = 0;  // (Optional) Needed for copies only.
    uint32_t height = 0;
    uint32_t usage = 0;  // TextureUsageBits the image was created with (informational).
};
Result WrapTextureVulkan(Device& device, const TextureVulkanDesc& desc, Texture*& out);

// An application command buffer in the recording state, as an rhi command buffer (no allocation;
// the pointer is the handle itself). Valid while 'commandBuffer' is.
inline CommandBuffer& GetCommandBuffer(VkCommandBuffer commandBuffer)
{
    return *reinterpret_cast<CommandBuffer*>(commandBuffer);
}
inline VkCommandBuffer GetVkCommandBuffer(CommandBuffer& commandBuffer)
{
    return reinterpret_cast<VkCommandBuffer>(&commandBuffer);
}

// Native handles of rhi objects created by a Vulkan device.
VkImage GetVkImage(const Texture& texture);
VkImageView GetVkImageView(const Texture& texture);
VkBuffer GetVkBuffer(const Buffer& buffer);

// Format and layout conversions. VK_FORMAT_UNDEFINED / Format::UNKNOWN where there is no match;
// FromVkImageLayout returns false for layouts Layout cannot express.
VkFormat ToVkFormat(Format format);
Format FromVkFormat(VkFormat format);
VkImageLayout ToVkImageLayout(Layout layout);
bool FromVkImageLayout(VkImageLayout vkLayout, Layout& outLayout);
VkResult ToVkResult(Result result);

} // namespace rhi
} // namespace nrd
