#include "VulkanContext.h"

#include "RHIVulkan.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>

namespace nrd
{
namespace lab
{
namespace
{

const char* VALIDATION_LAYER = "VK_LAYER_KHRONOS_validation";

bool HasLayer(const char* name)
{
    uint32_t num = 0;
    vkEnumerateInstanceLayerProperties(&num, nullptr);
    std::vector<VkLayerProperties> layers(num);
    vkEnumerateInstanceLayerProperties(&num, layers.data());
    for (const VkLayerProperties& layer : layers)
    {
        if (std::strcmp(layer.layerName, name) == 0)
            return true;
    }
    return false;
}

bool HasInstanceExtension(const char* name)
{
    uint32_t num = 0;
    vkEnumerateInstanceExtensionProperties(nullptr, &num, nullptr);
    std::vector<VkExtensionProperties> extensions(num);
    vkEnumerateInstanceExtensionProperties(nullptr, &num, extensions.data());
    for (const VkExtensionProperties& extension : extensions)
    {
        if (std::strcmp(extension.extensionName, name) == 0)
            return true;
    }
    return false;
}

const char* DeviceTypeString(VkPhysicalDeviceType type)
{
    switch (type)
    {
    case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU:
        return "discrete GPU";
    case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU:
        return "integrated GPU";
    case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU:
        return "virtual GPU";
    case VK_PHYSICAL_DEVICE_TYPE_CPU:
        return "CPU";
    default:
        return "other";
    }
}

// IEEE 754 binary16 <-> binary32, round to nearest even, with denormals, Inf and NaN.
uint16_t FloatToHalf(float value)
{
    uint32_t f;
    std::memcpy(&f, &value, 4);
    uint32_t sign = (f >> 16) & 0x8000u;
    uint32_t exponent = (f >> 23) & 0xFFu;
    uint32_t mantissa = f & 0x7FFFFFu;
    if (exponent == 0xFF) // Inf / NaN (keep NaN quiet).
        return (uint16_t)(sign | 0x7C00u | (mantissa ? 0x200u : 0u));
    int32_t e = (int32_t)exponent - 127 + 15;
    if (e >= 31) // Overflow -> Inf.
        return (uint16_t)(sign | 0x7C00u);
    if (e <= 0) // Denormal or zero.
    {
        if (e < -10)
            return (uint16_t)sign;
        mantissa |= 0x800000u;
        uint32_t shift = (uint32_t)(14 - e);
        uint32_t half = mantissa >> shift;
        uint32_t rest = mantissa & ((1u << shift) - 1);
        uint32_t midpoint = 1u << (shift - 1);
        if (rest > midpoint || (rest == midpoint && (half & 1)))
            half++;
        return (uint16_t)(sign | half);
    }
    uint32_t half = sign | ((uint32_t)e << 10) | (mantissa >> 13);
    uint32_t rest = mantissa & 0x1FFFu;
    if (rest > 0x1000u || (rest == 0x1000u && (half & 1)))
        half++; // May carry into the exponent, which is still correct (up to Inf).
    return (uint16_t)half;
}

float HalfToFloat(uint16_t h)
{
    uint32_t sign = (uint32_t)(h & 0x8000u) << 16;
    uint32_t exponent = (h >> 10) & 0x1Fu;
    uint32_t mantissa = h & 0x3FFu;
    uint32_t f;
    if (exponent == 0x1F)
        f = sign | 0x7F800000u | (mantissa << 13);
    else if (exponent != 0)
        f = sign | ((exponent - 15 + 127) << 23) | (mantissa << 13);
    else if (mantissa == 0)
        f = sign;
    else
    {
        // Denormal: normalize.
        int32_t e = -1;
        do
        {
            e++;
            mantissa <<= 1;
        } while (!(mantissa & 0x400u));
        f = sign | ((uint32_t)(127 - 15 - e) << 23) | ((mantissa & 0x3FFu) << 13);
    }
    float value;
    std::memcpy(&value, &f, 4);
    return value;
}

uint32_t ToUnorm(float value, uint32_t maxValue)
{
    float clamped = std::isnan(value) ? 0.0f : std::min(std::max(value, 0.0f), 1.0f);
    return (uint32_t)std::lround(clamped * (float)maxValue);
}

uint32_t ToUint(float value, uint32_t maxValue)
{
    if (std::isnan(value) || value <= 0.0f)
        return 0;
    return value >= (float)maxValue ? maxValue : (uint32_t)value;
}

enum class Channel
{
    UNORM8,
    UNORM16,
    FLOAT16,
    FLOAT32,
    UINT16,
    UINT32,
    NONE,
};

Channel ChannelOf(rhi::Format format)
{
    switch (format)
    {
    case rhi::Format::R8_UNORM:
    case rhi::Format::RG8_UNORM:
    case rhi::Format::RGBA8_UNORM:
    case rhi::Format::RGBA8_SRGB: // Raw encoded values, no sRGB curve.
    case rhi::Format::BGRA8_UNORM: // Memory order (B first).
        return Channel::UNORM8;
    case rhi::Format::R16_UNORM:
        return Channel::UNORM16;
    case rhi::Format::R16_SFLOAT:
    case rhi::Format::RG16_SFLOAT:
    case rhi::Format::RGBA16_SFLOAT:
        return Channel::FLOAT16;
    case rhi::Format::R32_SFLOAT:
    case rhi::Format::RG32_SFLOAT:
    case rhi::Format::RGBA32_SFLOAT:
        return Channel::FLOAT32;
    case rhi::Format::R16_UINT:
        return Channel::UINT16;
    case rhi::Format::R32_UINT:
    case rhi::Format::RG32_UINT:
    case rhi::Format::RGBA32_UINT:
        return Channel::UINT32;
    default:
        return Channel::NONE;
    }
}

} // namespace

bool PackPixels(rhi::Format format, const float* pixels, size_t pixelsNum, void* bytes)
{
    size_t valuesNum = pixelsNum * rhi::GetFormatInfo(format).channelNum;
    uint8_t* u8 = (uint8_t*)bytes;
    uint16_t* u16 = (uint16_t*)bytes;
    uint32_t* u32 = (uint32_t*)bytes;
    float* f32 = (float*)bytes;
    switch (ChannelOf(format))
    {
    case Channel::UNORM8:
        for (size_t i = 0; i < valuesNum; i++)
            u8[i] = (uint8_t)ToUnorm(pixels[i], 255);
        return true;
    case Channel::UNORM16:
        for (size_t i = 0; i < valuesNum; i++)
            u16[i] = (uint16_t)ToUnorm(pixels[i], 65535);
        return true;
    case Channel::FLOAT16:
        for (size_t i = 0; i < valuesNum; i++)
            u16[i] = FloatToHalf(pixels[i]);
        return true;
    case Channel::FLOAT32:
        std::memcpy(f32, pixels, valuesNum * sizeof(float));
        return true;
    case Channel::UINT16:
        for (size_t i = 0; i < valuesNum; i++)
            u16[i] = (uint16_t)ToUint(pixels[i], 65535);
        return true;
    case Channel::UINT32:
        for (size_t i = 0; i < valuesNum; i++)
            u32[i] = ToUint(pixels[i], 0xFFFFFFFFu);
        return true;
    case Channel::NONE:
        break;
    }
    if (format == rhi::Format::R10_G10_B10_A2_UNORM)
    {
        for (size_t i = 0; i < pixelsNum; i++)
        {
            const float* p = pixels + i * 4;
            u32[i] = ToUnorm(p[0], 1023) | (ToUnorm(p[1], 1023) << 10) | (ToUnorm(p[2], 1023) << 20) |
                     (ToUnorm(p[3], 3) << 30);
        }
        return true;
    }
    return false;
}

bool UnpackPixels(rhi::Format format, const void* bytes, size_t pixelsNum, float* pixels)
{
    size_t valuesNum = pixelsNum * rhi::GetFormatInfo(format).channelNum;
    const uint8_t* u8 = (const uint8_t*)bytes;
    const uint16_t* u16 = (const uint16_t*)bytes;
    const uint32_t* u32 = (const uint32_t*)bytes;
    switch (ChannelOf(format))
    {
    case Channel::UNORM8:
        for (size_t i = 0; i < valuesNum; i++)
            pixels[i] = u8[i] / 255.0f;
        return true;
    case Channel::UNORM16:
        for (size_t i = 0; i < valuesNum; i++)
            pixels[i] = u16[i] / 65535.0f;
        return true;
    case Channel::FLOAT16:
        for (size_t i = 0; i < valuesNum; i++)
            pixels[i] = HalfToFloat(u16[i]);
        return true;
    case Channel::FLOAT32:
        std::memcpy(pixels, bytes, valuesNum * sizeof(float));
        return true;
    case Channel::UINT16:
        for (size_t i = 0; i < valuesNum; i++)
            pixels[i] = (float)u16[i];
        return true;
    case Channel::UINT32:
        for (size_t i = 0; i < valuesNum; i++)
            pixels[i] = (float)u32[i];
        return true;
    case Channel::NONE:
        break;
    }
    if (format == rhi::Format::R10_G10_B10_A2_UNORM)
    {
        for (size_t i = 0; i < pixelsNum; i++)
        {
            float* p = pixels + i * 4;
            p[0] = (u32[i] & 1023) / 1023.0f;
            p[1] = ((u32[i] >> 10) & 1023) / 1023.0f;
            p[2] = ((u32[i] >> 20) & 1023) / 1023.0f;
            p[3] = (u32[i] >> 30) / 3.0f;
        }
        return true;
    }
    return false;
}

UserTexture LabTexture::AsUserTexture() const
{
    UserTexture user = {};
    user.image = rhi::GetVkImage(*texture);
    user.view = rhi::GetVkImageView(*texture);
    user.format = rhi::ToVkFormat(format);
    user.layout = rhi::ToVkImageLayout(state.layout);
    return user;
}

void LabTexture::FromUserTexture(const UserTexture& user)
{
    rhi::FromVkImageLayout(user.layout, state.layout);
    state.access = rhi::ACCESS_SHADER_READ_WRITE; // A compute shader, possibly writing.
}

VKAPI_ATTR VkBool32 VKAPI_CALL VulkanContext::OnValidationMessage(VkDebugUtilsMessageSeverityFlagBitsEXT severity,
                                                                  VkDebugUtilsMessageTypeFlagsEXT,
                                                                  const VkDebugUtilsMessengerCallbackDataEXT* data,
                                                                  void* userData)
{
    VulkanContext* context = (VulkanContext*)userData;
    if (severity >= VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT)
    {
        context->m_ValidationMessageCount++;
        std::fprintf(stderr, "[Vulkan %s] %s\n",
                     severity >= VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT ? "error" : "warning",
                     data && data->pMessage ? data->pMessage : "");
    }
    return VK_FALSE;
}

VkResult VulkanContext::Create(const VulkanContextDesc& desc)
{
    Destroy();
    VkResult result = CreateInstance(desc);
    if (result == VK_SUCCESS)
        result = CreateDevice(desc);
    if (result == VK_SUCCESS)
    {
        rhi::DeviceVulkanDesc rhiDesc = {};
        rhiDesc.instance = m_Instance;
        rhiDesc.physicalDevice = m_PhysicalDevice;
        rhiDesc.device = m_Device;
        rhiDesc.queueFamilyIndex = m_QueueFamilyIndex;
        rhiDesc.queue = m_Queue;
        VkPhysicalDeviceFeatures features = {};
        vkGetPhysicalDeviceFeatures(m_PhysicalDevice, &features);
        rhiDesc.storageImageReadWithoutFormatEnabled = features.shaderStorageImageReadWithoutFormat;
        rhiDesc.storageImageWriteWithoutFormatEnabled = features.shaderStorageImageWriteWithoutFormat;
        result = rhi::ToVkResult(rhi::CreateDeviceVulkan(rhiDesc, m_Rhi));
    }
    if (result != VK_SUCCESS)
    {
        std::fprintf(stderr, "VulkanContext: creation failed (VkResult %d)\n", (int)result);
        Destroy();
    }
    return result;
}

VkResult VulkanContext::CreateInstance(const VulkanContextDesc& desc)
{
    std::vector<const char*> layers;
    std::vector<const char*> extensions;
    bool validation = desc.enableValidation && HasLayer(VALIDATION_LAYER);
    if (desc.enableValidation && !validation)
        std::fprintf(stderr, "VulkanContext: %s is not installed; running without validation\n", VALIDATION_LAYER);
    if (validation)
        layers.push_back(VALIDATION_LAYER);
    bool debugUtils = HasInstanceExtension(VK_EXT_DEBUG_UTILS_EXTENSION_NAME);
    if (debugUtils)
        extensions.push_back(VK_EXT_DEBUG_UTILS_EXTENSION_NAME);
    validation = validation && debugUtils;

    uint32_t apiVersion = VK_API_VERSION_1_1;
    vkEnumerateInstanceVersion(&apiVersion);
    VkApplicationInfo appInfo = {VK_STRUCTURE_TYPE_APPLICATION_INFO};
    appInfo.pApplicationName = desc.applicationName;
    appInfo.pEngineName = "NRD";
    appInfo.apiVersion = std::min(apiVersion, (uint32_t)VK_API_VERSION_1_3);

    VkDebugUtilsMessengerCreateInfoEXT messengerInfo = {VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT};
    messengerInfo.messageSeverity = VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT |
                                    VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
    messengerInfo.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT |
                                VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT |
                                VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT;
    messengerInfo.pfnUserCallback = OnValidationMessage;
    messengerInfo.pUserData = this;

    VkValidationFeatureEnableEXT enabledFeatures[] = {VK_VALIDATION_FEATURE_ENABLE_SYNCHRONIZATION_VALIDATION_EXT};
    VkValidationFeaturesEXT validationFeatures = {VK_STRUCTURE_TYPE_VALIDATION_FEATURES_EXT};
    validationFeatures.enabledValidationFeatureCount = 1;
    validationFeatures.pEnabledValidationFeatures = enabledFeatures;
    validationFeatures.pNext = &messengerInfo; // Also reports instance creation / destruction.

    VkInstanceCreateInfo info = {VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
    info.pApplicationInfo = &appInfo;
    info.enabledLayerCount = (uint32_t)layers.size();
    info.ppEnabledLayerNames = layers.data();
    info.enabledExtensionCount = (uint32_t)extensions.size();
    info.ppEnabledExtensionNames = extensions.data();
    if (validation)
        info.pNext = desc.enableSynchronizationValidation ? (const void*)&validationFeatures : (const void*)&messengerInfo;

    VkResult result = vkCreateInstance(&info, nullptr, &m_Instance);
    if (result != VK_SUCCESS || !validation)
        return result;

    auto createMessenger = (PFN_vkCreateDebugUtilsMessengerEXT)vkGetInstanceProcAddr(m_Instance,
                                                                                   "vkCreateDebugUtilsMessengerEXT");
    return createMessenger ? createMessenger(m_Instance, &messengerInfo, nullptr, &m_Messenger) : VK_SUCCESS;
}

VkResult VulkanContext::CreateDevice(const VulkanContextDesc& desc)
{
    uint32_t num = 0;
    vkEnumeratePhysicalDevices(m_Instance, &num, nullptr);
    std::vector<VkPhysicalDevice> devices(num);
    vkEnumeratePhysicalDevices(m_Instance, &num, devices.data());
    if (devices.empty())
    {
        std::fprintf(stderr, "VulkanContext: no Vulkan device\n");
        return VK_ERROR_INITIALIZATION_FAILED;
    }

    uint32_t index = 0;
    if (desc.deviceIndex >= 0)
    {
        if ((uint32_t)desc.deviceIndex >= num)
        {
            std::fprintf(stderr, "VulkanContext: device index %d out of range (%u devices)\n", desc.deviceIndex, num);
            return VK_ERROR_INITIALIZATION_FAILED;
        }
        index = (uint32_t)desc.deviceIndex;
    }
    else
    {
        for (uint32_t i = num; i-- > 0;) // The first discrete GPU wins.
        {
            VkPhysicalDeviceProperties properties = {};
            vkGetPhysicalDeviceProperties(devices[i], &properties);
            if (properties.deviceType == VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU)
                index = i;
        }
    }
    m_PhysicalDevice = devices[index];
    vkGetPhysicalDeviceProperties(m_PhysicalDevice, &m_Properties);
    if (!desc.quiet)
        std::printf("VulkanContext: device %u: %s (%s, Vulkan %u.%u.%u)\n", index, m_Properties.deviceName,
                    DeviceTypeString(m_Properties.deviceType), VK_API_VERSION_MAJOR(m_Properties.apiVersion),
                    VK_API_VERSION_MINOR(m_Properties.apiVersion), VK_API_VERSION_PATCH(m_Properties.apiVersion));

    uint32_t familyNum = 0;
    vkGetPhysicalDeviceQueueFamilyProperties(m_PhysicalDevice, &familyNum, nullptr);
    std::vector<VkQueueFamilyProperties> families(familyNum);
    vkGetPhysicalDeviceQueueFamilyProperties(m_PhysicalDevice, &familyNum, families.data());
    m_QueueFamilyIndex = familyNum;
    for (uint32_t i = 0; i < familyNum && m_QueueFamilyIndex == familyNum; i++)
    {
        if (families[i].queueFlags & VK_QUEUE_COMPUTE_BIT)
            m_QueueFamilyIndex = i;
    }
    if (m_QueueFamilyIndex == familyNum)
    {
        std::fprintf(stderr, "VulkanContext: no compute queue\n");
        return VK_ERROR_FEATURE_NOT_PRESENT;
    }

    // Features the SDK and the samples need: user outputs are storage images without a format
    // qualifier; pool textures use extended storage formats (r8, rg16f...).
    VkPhysicalDeviceFeatures supported = {};
    vkGetPhysicalDeviceFeatures(m_PhysicalDevice, &supported);
    if (!supported.shaderStorageImageWriteWithoutFormat)
    {
        std::fprintf(stderr, "VulkanContext: shaderStorageImageWriteWithoutFormat is not supported\n");
        return VK_ERROR_FEATURE_NOT_PRESENT;
    }
    VkPhysicalDeviceFeatures features = {};
    features.shaderStorageImageWriteWithoutFormat = VK_TRUE;
    features.shaderStorageImageReadWithoutFormat = supported.shaderStorageImageReadWithoutFormat;
    features.shaderStorageImageExtendedFormats = supported.shaderStorageImageExtendedFormats;
    features.shaderInt16 = supported.shaderInt16;
    features.shaderInt64 = supported.shaderInt64;

    float priority = 1.0f;
    VkDeviceQueueCreateInfo queueInfo = {VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
    queueInfo.queueFamilyIndex = m_QueueFamilyIndex;
    queueInfo.queueCount = 1;
    queueInfo.pQueuePriorities = &priority;

    VkDeviceCreateInfo info = {VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO};
    info.queueCreateInfoCount = 1;
    info.pQueueCreateInfos = &queueInfo;
    info.pEnabledFeatures = &features;
    VkResult result = vkCreateDevice(m_PhysicalDevice, &info, nullptr, &m_Device);
    if (result == VK_SUCCESS)
        vkGetDeviceQueue(m_Device, m_QueueFamilyIndex, 0, &m_Queue);
    return result;
}

void VulkanContext::Destroy()
{
    if (m_Device)
        vkDeviceWaitIdle(m_Device);
    rhi::DestroyDevice(m_Rhi);
    m_Rhi = nullptr;
    if (m_Device)
        vkDestroyDevice(m_Device, nullptr);
    m_Device = VK_NULL_HANDLE;
    m_Queue = VK_NULL_HANDLE;
    if (m_Messenger)
    {
        auto destroyMessenger = (PFN_vkDestroyDebugUtilsMessengerEXT)vkGetInstanceProcAddr(
            m_Instance, "vkDestroyDebugUtilsMessengerEXT");
        if (destroyMessenger)
            destroyMessenger(m_Instance, m_Messenger, nullptr);
    }
    m_Messenger = VK_NULL_HANDLE;
    if (m_Instance)
        vkDestroyInstance(m_Instance, nullptr);
    m_Instance = VK_NULL_HANDLE;
    m_PhysicalDevice = VK_NULL_HANDLE;
}

IntegrationCreationDesc VulkanContext::GetIntegrationCreationDesc() const
{
    IntegrationCreationDesc desc = {};
    desc.instance = m_Instance;
    desc.physicalDevice = m_PhysicalDevice;
    desc.device = m_Device;
    desc.queueFamilyIndex = m_QueueFamilyIndex;
    return desc;
}

VkResult VulkanContext::BeginCommands(VkCommandBuffer& out)
{
    out = VK_NULL_HANDLE;
    rhi::CommandBuffer* cmd = nullptr;
    rhi::Result result = m_Rhi->CreateCommandBuffer(cmd);
    if (result == rhi::Result::SUCCESS)
    {
        result = m_Rhi->BeginCommandBuffer(*cmd);
        if (result != rhi::Result::SUCCESS)
            m_Rhi->DestroyCommandBuffer(cmd);
    }
    if (result == rhi::Result::SUCCESS)
        out = rhi::GetVkCommandBuffer(*cmd);
    return rhi::ToVkResult(result);
}

VkResult VulkanContext::SubmitAndWait(VkCommandBuffer commandBuffer)
{
    rhi::CommandBuffer& cmd = rhi::GetCommandBuffer(commandBuffer);
    rhi::Result result = m_Rhi->EndCommandBuffer(cmd);
    if (result == rhi::Result::SUCCESS)
        result = m_Rhi->SubmitAndWait(cmd);
    m_Rhi->DestroyCommandBuffer(&cmd);
    return rhi::ToVkResult(result);
}

VkResult VulkanContext::CreateTexture(rhi::Format format, uint32_t width, uint32_t height, const char* name,
                                      LabTexture& out)
{
    out = {};
    rhi::TextureDesc desc = {};
    desc.format = format;
    desc.width = width;
    desc.height = height;
    desc.usage = rhi::TEXTURE_USAGE_SAMPLED | rhi::TEXTURE_USAGE_STORAGE | rhi::TEXTURE_USAGE_COPY_SOURCE |
                 rhi::TEXTURE_USAGE_COPY_DESTINATION;
    desc.name = name;
    VkResult result = rhi::ToVkResult(m_Rhi->CreateTexture(desc, out.texture));
    if (result == VK_SUCCESS)
    {
        out.format = format;
        out.width = width;
        out.height = height;
    }
    return result;
}

void VulkanContext::DestroyTexture(LabTexture& texture)
{
    if (m_Rhi)
        m_Rhi->DestroyTexture(texture.texture);
    texture = {};
}

VkResult VulkanContext::UploadTexture(LabTexture& texture, const float* pixels, rhi::Layout finalLayout)
{
    size_t pixelsNum = (size_t)texture.width * texture.height;
    rhi::BufferDesc stagingDesc = {};
    stagingDesc.size = pixelsNum * rhi::GetFormatBytesPerPixel(texture.format);
    stagingDesc.usage = rhi::BUFFER_USAGE_COPY_SOURCE;
    stagingDesc.location = rhi::MemoryLocation::HOST_UPLOAD;
    stagingDesc.name = "LabTexture upload";
    rhi::Buffer* staging = nullptr;
    VkResult result = rhi::ToVkResult(m_Rhi->CreateBuffer(stagingDesc, staging));
    if (result != VK_SUCCESS)
        return result;
    if (!PackPixels(texture.format, pixels, pixelsNum, m_Rhi->MapBuffer(*staging)))
    {
        m_Rhi->DestroyBuffer(staging);
        return VK_ERROR_FORMAT_NOT_SUPPORTED;
    }

    VkCommandBuffer commandBuffer = VK_NULL_HANDLE;
    result = BeginCommands(commandBuffer);
    if (result == VK_SUCCESS)
    {
        rhi::CommandBuffer& cmd = rhi::GetCommandBuffer(commandBuffer);
        // WAW / WAR against whatever used the texture last; the host wrote 'staging' before the
        // submission, which makes those writes visible.
        rhi::TextureState copyState = {rhi::ACCESS_COPY_DESTINATION, rhi::Layout::COPY_DESTINATION};
        rhi::TextureBarrier toCopy = {texture.texture, texture.state, copyState};
        m_Rhi->CmdBarrier(cmd, {nullptr, 0, nullptr, 0, &toCopy, 1});
        m_Rhi->CmdCopyBufferToTexture(cmd, *texture.texture, *staging, 0);
        texture.state = copyState;
        if (finalLayout != rhi::Layout::COPY_DESTINATION)
        {
            // RAW: later shader reads (or storage accesses) wait for the copy.
            uint32_t access = finalLayout == rhi::Layout::GENERAL ? rhi::ACCESS_SHADER_READ_WRITE : rhi::ACCESS_SHADER_READ;
            rhi::TextureBarrier toFinal = {texture.texture, copyState, {access, finalLayout}};
            m_Rhi->CmdBarrier(cmd, {nullptr, 0, nullptr, 0, &toFinal, 1});
            texture.state = toFinal.after;
        }
        result = SubmitAndWait(commandBuffer);
    }
    m_Rhi->DestroyBuffer(staging);
    return result;
}

VkResult VulkanContext::ReadbackTexture(LabTexture& texture, std::vector<float>& outPixels)
{
    size_t pixelsNum = (size_t)texture.width * texture.height;
    rhi::BufferDesc readbackDesc = {};
    readbackDesc.size = pixelsNum * rhi::GetFormatBytesPerPixel(texture.format);
    readbackDesc.usage = rhi::BUFFER_USAGE_COPY_DESTINATION;
    readbackDesc.location = rhi::MemoryLocation::HOST_READBACK;
    readbackDesc.name = "LabTexture readback";
    rhi::Buffer* readback = nullptr;
    VkResult result = rhi::ToVkResult(m_Rhi->CreateBuffer(readbackDesc, readback));
    if (result != VK_SUCCESS)
        return result;

    VkCommandBuffer commandBuffer = VK_NULL_HANDLE;
    result = BeginCommands(commandBuffer);
    if (result == VK_SUCCESS)
    {
        rhi::CommandBuffer& cmd = rhi::GetCommandBuffer(commandBuffer);
        // RAW: the copy reads what the last user of the texture wrote.
        rhi::TextureState copyState = {rhi::ACCESS_COPY_SOURCE, rhi::Layout::COPY_SOURCE};
        rhi::TextureBarrier toCopy = {texture.texture, texture.state, copyState};
        m_Rhi->CmdBarrier(cmd, {nullptr, 0, nullptr, 0, &toCopy, 1});
        m_Rhi->CmdCopyTextureToBuffer(cmd, *readback, 0, *texture.texture);
        texture.state = copyState;
        // RAW: the host reads what the copy wrote.
        rhi::BufferBarrier toHost = {readback, rhi::ACCESS_COPY_DESTINATION, rhi::ACCESS_HOST_READ};
        m_Rhi->CmdBarrier(cmd, {nullptr, 0, &toHost, 1, nullptr, 0});
        result = SubmitAndWait(commandBuffer);
    }
    if (result == VK_SUCCESS)
    {
        outPixels.resize(pixelsNum * rhi::GetFormatInfo(texture.format).channelNum);
        if (!UnpackPixels(texture.format, m_Rhi->MapBuffer(*readback), pixelsNum, outPixels.data()))
            result = VK_ERROR_FORMAT_NOT_SUPPORTED;
    }
    m_Rhi->DestroyBuffer(readback);
    return result;
}

VkResult VulkanContext::ReadbackBuffer(rhi::Buffer& buffer, uint32_t lastAccess, uint64_t size,
                                       std::vector<uint32_t>& outWords)
{
    rhi::BufferDesc readbackDesc = {};
    readbackDesc.size = size;
    readbackDesc.usage = rhi::BUFFER_USAGE_COPY_DESTINATION;
    readbackDesc.location = rhi::MemoryLocation::HOST_READBACK;
    readbackDesc.name = "Buffer readback";
    rhi::Buffer* readback = nullptr;
    VkResult result = rhi::ToVkResult(m_Rhi->CreateBuffer(readbackDesc, readback));
    if (result != VK_SUCCESS)
        return result;
    VkCommandBuffer commandBuffer = VK_NULL_HANDLE;
    result = BeginCommands(commandBuffer);
    if (result == VK_SUCCESS)
    {
        rhi::CommandBuffer& cmd = rhi::GetCommandBuffer(commandBuffer);
        // RAW: the copy reads what the last user wrote.
        rhi::BufferBarrier toCopy = {&buffer, lastAccess, rhi::ACCESS_COPY_SOURCE};
        m_Rhi->CmdBarrier(cmd, {nullptr, 0, &toCopy, 1, nullptr, 0});
        m_Rhi->CmdCopyBuffer(cmd, *readback, 0, buffer, 0, size);
        // RAW: the host reads what the copy wrote.
        rhi::BufferBarrier toHost = {readback, rhi::ACCESS_COPY_DESTINATION, rhi::ACCESS_HOST_READ};
        m_Rhi->CmdBarrier(cmd, {nullptr, 0, &toHost, 1, nullptr, 0});
        result = SubmitAndWait(commandBuffer);
    }
    if (result == VK_SUCCESS)
    {
        const uint32_t* words = static_cast<const uint32_t*>(m_Rhi->MapBuffer(*readback));
        outWords.assign(words, words + size / sizeof(uint32_t));
    }
    m_Rhi->DestroyBuffer(readback);
    return result;
}

} // namespace lab
} // namespace nrd
