// Headless Vulkan context for the samples, tests and benchmark: instance (+ validation on request),
// physical device, device with one compute queue, and an nrd::rhi device over it. Everything else
// (textures, buffers, pipelines, command buffers) goes through nrd::rhi; the helpers below only add
// "upload / read back float pixels" on top of it.
#pragma once

#include "NRDIntegration.h"
#include "RHI.h"

#include <vulkan/vulkan.h>

#include <atomic>
#include <cstdint>
#include <vector>

namespace nrd
{
namespace lab
{

struct VulkanContextDesc
{
    // Loads VK_LAYER_KHRONOS_validation (if installed; a warning is printed otherwise) with a
    // messenger that prints and counts every warning and error.
    bool enableValidation = false;
    // With validation: also synchronization validation (hazards between commands).
    bool enableSynchronizationValidation = true;
    // Index into vkEnumeratePhysicalDevices; -1 picks the first discrete GPU, else the first device.
    int32_t deviceIndex = -1;
    const char* applicationName = "NRD lab";
    bool quiet = false; // Do not print the chosen device.
};

// A device-local 2D texture created through rhi, with the state it was last left in.
struct LabTexture
{
    rhi::Texture* texture = nullptr;
    rhi::Format format = rhi::Format::UNKNOWN;
    uint32_t width = 0;
    uint32_t height = 0;
    rhi::TextureState state = {}; // Tracked by the helpers; update it after recording other uses.

    // As an Integration user texture (in its current layout).
    UserTexture AsUserTexture() const;
    // Takes back the layout Integration::Denoise left it in (last access: a compute shader).
    void FromUserTexture(const UserTexture& user);
};

class VulkanContext
{
public:
    VulkanContext() = default;
    ~VulkanContext()
    {
        Destroy();
    }
    VulkanContext(const VulkanContext&) = delete;
    VulkanContext& operator=(const VulkanContext&) = delete;

    // Creates instance, device, queue and rhi device. On failure prints why and leaves nothing.
    VkResult Create(const VulkanContextDesc& desc);
    // Waits for the device to be idle, then destroys everything. Safe to call twice.
    void Destroy();

    VkInstance GetInstance() const { return m_Instance; }
    VkPhysicalDevice GetPhysicalDevice() const { return m_PhysicalDevice; }
    VkDevice GetVkDevice() const { return m_Device; }
    VkQueue GetQueue() const { return m_Queue; }
    uint32_t GetQueueFamilyIndex() const { return m_QueueFamilyIndex; }
    rhi::Device& GetDevice() { return *m_Rhi; }
    const VkPhysicalDeviceProperties& GetProperties() const { return m_Properties; }

    // True if the validation layer is active (requested and installed).
    bool IsValidationEnabled() const { return m_Messenger != VK_NULL_HANDLE; }
    // Validation messages of warning or error severity so far (each was printed to stderr).
    uint32_t ValidationMessageCount() const { return m_ValidationMessageCount.load(); }

    // Filled for this context's device, queue family and instance.
    IntegrationCreationDesc GetIntegrationCreationDesc() const;

    // One-shot command buffer: Begin, record, SubmitAndWait (which frees it).
    VkResult BeginCommands(VkCommandBuffer& out);
    VkResult SubmitAndWait(VkCommandBuffer commandBuffer);

    // Device-local texture with usage sampled + storage + copy source / destination, state UNDEFINED.
    VkResult CreateTexture(rhi::Format format, uint32_t width, uint32_t height, const char* name, LabTexture& out);
    void DestroyTexture(LabTexture& texture);

    // Converts 'pixels' (width * height * GetFormatInfo(format).channelNum floats, row-major, top row
    // first) to the texture's format, uploads them and leaves the texture in 'finalLayout'
    // (COPY_DESTINATION, SHADER_RESOURCE or GENERAL). Waits for completion.
    // VK_ERROR_FORMAT_NOT_SUPPORTED for formats without a converter (R11_G11_B10_UFLOAT).
    VkResult UploadTexture(LabTexture& texture, const float* pixels,
                           rhi::Layout finalLayout = rhi::Layout::SHADER_RESOURCE);
    // Reads the whole texture back as floats (same layout as UploadTexture). Waits for completion;
    // leaves the texture in COPY_SOURCE.
    VkResult ReadbackTexture(LabTexture& texture, std::vector<float>& outPixels);
    // Reads the first 'size' bytes (a multiple of 4) of a buffer back as uint32 words. 'lastAccess'
    // (rhi::AccessBits) is what last touched it; the copy waits for it. Waits for completion.
    VkResult ReadbackBuffer(rhi::Buffer& buffer, uint32_t lastAccess, uint64_t size, std::vector<uint32_t>& outWords);

private:
    static VKAPI_ATTR VkBool32 VKAPI_CALL OnValidationMessage(VkDebugUtilsMessageSeverityFlagBitsEXT severity,
                                                              VkDebugUtilsMessageTypeFlagsEXT types,
                                                              const VkDebugUtilsMessengerCallbackDataEXT* data,
                                                              void* userData);
    VkResult CreateInstance(const VulkanContextDesc& desc);
    VkResult CreateDevice(const VulkanContextDesc& desc);

    VkInstance m_Instance = VK_NULL_HANDLE;
    VkDebugUtilsMessengerEXT m_Messenger = VK_NULL_HANDLE; // Only with validation.
    VkPhysicalDevice m_PhysicalDevice = VK_NULL_HANDLE;
    VkPhysicalDeviceProperties m_Properties = {};
    VkDevice m_Device = VK_NULL_HANDLE;
    VkQueue m_Queue = VK_NULL_HANDLE;
    uint32_t m_QueueFamilyIndex = 0;
    rhi::Device* m_Rhi = nullptr;
    std::atomic<uint32_t> m_ValidationMessageCount{0};
};

// Pixel conversions used by UploadTexture / ReadbackTexture ('pixelsNum' pixels of 'format';
// 'bytes' holds pixelsNum * GetFormatBytesPerPixel). False if the format has no converter.
bool PackPixels(rhi::Format format, const float* pixels, size_t pixelsNum, void* bytes);
bool UnpackPixels(rhi::Format format, const void* bytes, size_t pixelsNum, float* pixels);

} // namespace lab
} // namespace nrd
