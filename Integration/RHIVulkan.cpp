// Vulkan backend of nrd::rhi (RHI.h, RHIVulkan.h).
//
// Plain Vulkan 1.1 with synchronization 1 barriers. Every texture and buffer gets its own
// VkDeviceMemory: the executor creates tens of resources, not thousands; an engine would
// sub-allocate.
#include "RHIVulkan.h"

#include <cstring>
#include <new>
#include <string>
#include <vector>

namespace nrd
{
namespace rhi
{
namespace
{

// Backend objects behind the opaque rhi types (cast with To / From below).
struct TextureVK
{
    TextureDesc desc = {};          // 'desc.name' points at 'name'.
    std::string name;
    VkImage image = VK_NULL_HANDLE;
    VkImageView view = VK_NULL_HANDLE;
    VkDeviceMemory memory = VK_NULL_HANDLE; // Null for wrapped images.
    VkFormat vkFormat = VK_FORMAT_UNDEFINED;
    uint64_t memorySize = 0;
};

struct BufferVK
{
    BufferDesc desc = {};
    std::string name;
    VkBuffer buffer = VK_NULL_HANDLE;
    VkDeviceMemory memory = VK_NULL_HANDLE;
    void* mapped = nullptr; // Host-visible buffers stay mapped.
    uint64_t memorySize = 0;
};

struct SamplerVK
{
    VkSampler sampler = VK_NULL_HANDLE;
};

struct PipelineVK
{
    VkPipeline pipeline = VK_NULL_HANDLE;
    VkPipelineLayout layout = VK_NULL_HANDLE;
    std::vector<VkDescriptorSetLayout> setLayouts;
};

struct DescriptorSetVK
{
    VkDescriptorSet set = VK_NULL_HANDLE;
};

struct DescriptorPoolVK
{
    VkDescriptorPool pool = VK_NULL_HANDLE;
    std::vector<DescriptorSetVK> sets; // Capacity reserved up front: pointers stay valid until reset.
};

struct QueryPoolVK
{
    VkQueryPool pool = VK_NULL_HANDLE;
    uint32_t queryNum = 0;
};

template <typename T> struct Native;
template <> struct Native<Texture> { using Type = TextureVK; };
template <> struct Native<Buffer> { using Type = BufferVK; };
template <> struct Native<Sampler> { using Type = SamplerVK; };
template <> struct Native<Pipeline> { using Type = PipelineVK; };
template <> struct Native<DescriptorSet> { using Type = DescriptorSetVK; };
template <> struct Native<DescriptorPool> { using Type = DescriptorPoolVK; };
template <> struct Native<QueryPool> { using Type = QueryPoolVK; };

template <typename T> typename Native<T>::Type& To(T& object)
{
    return *reinterpret_cast<typename Native<T>::Type*>(&object);
}
template <typename T> const typename Native<T>::Type& To(const T& object)
{
    return *reinterpret_cast<const typename Native<T>::Type*>(&object);
}
template <typename T> T* From(typename Native<T>::Type* object)
{
    return reinterpret_cast<T*>(object);
}

VkCommandBuffer ToVk(CommandBuffer& cmd)
{
    return GetVkCommandBuffer(cmd);
}

Result FromVk(VkResult result)
{
    switch (result)
    {
    case VK_SUCCESS:
        return Result::SUCCESS;
    case VK_NOT_READY:
    case VK_TIMEOUT:
        return Result::NOT_READY;
    case VK_ERROR_OUT_OF_HOST_MEMORY:
    case VK_ERROR_OUT_OF_DEVICE_MEMORY:
    case VK_ERROR_OUT_OF_POOL_MEMORY:
    case VK_ERROR_FRAGMENTED_POOL:
    case VK_ERROR_FRAGMENTATION:
        return Result::OUT_OF_MEMORY;
    case VK_ERROR_FORMAT_NOT_SUPPORTED:
    case VK_ERROR_FEATURE_NOT_PRESENT:
    case VK_ERROR_EXTENSION_NOT_PRESENT:
        return Result::UNSUPPORTED;
    case VK_ERROR_DEVICE_LOST:
        return Result::DEVICE_LOST;
    default:
        return Result::FAILURE;
    }
}

// Stages and accesses implied by AccessBits (see RHI.h, "Synchronization").
VkPipelineStageFlags ToStages(uint32_t access)
{
    if (access & ACCESS_UNKNOWN)
        return VK_PIPELINE_STAGE_ALL_COMMANDS_BIT;
    VkPipelineStageFlags stages = 0;
    if (access & (ACCESS_SHADER_READ | ACCESS_SHADER_READ_WRITE | ACCESS_UNIFORM))
        stages |= VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT;
    if (access & ACCESS_INDIRECT_ARGUMENTS)
        stages |= VK_PIPELINE_STAGE_DRAW_INDIRECT_BIT;
    if (access & (ACCESS_COPY_SOURCE | ACCESS_COPY_DESTINATION))
        stages |= VK_PIPELINE_STAGE_TRANSFER_BIT;
    if (access & (ACCESS_HOST_READ | ACCESS_HOST_WRITE))
        stages |= VK_PIPELINE_STAGE_HOST_BIT;
    return stages;
}

VkAccessFlags ToAccess(uint32_t access)
{
    if (access & ACCESS_UNKNOWN)
        return VK_ACCESS_MEMORY_READ_BIT | VK_ACCESS_MEMORY_WRITE_BIT;
    VkAccessFlags flags = 0;
    if (access & ACCESS_SHADER_READ)
        flags |= VK_ACCESS_SHADER_READ_BIT;
    if (access & ACCESS_SHADER_READ_WRITE)
        flags |= VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT;
    if (access & ACCESS_UNIFORM)
        flags |= VK_ACCESS_UNIFORM_READ_BIT;
    if (access & ACCESS_INDIRECT_ARGUMENTS)
        flags |= VK_ACCESS_INDIRECT_COMMAND_READ_BIT;
    if (access & ACCESS_COPY_SOURCE)
        flags |= VK_ACCESS_TRANSFER_READ_BIT;
    if (access & ACCESS_COPY_DESTINATION)
        flags |= VK_ACCESS_TRANSFER_WRITE_BIT;
    if (access & ACCESS_HOST_READ)
        flags |= VK_ACCESS_HOST_READ_BIT;
    if (access & ACCESS_HOST_WRITE)
        flags |= VK_ACCESS_HOST_WRITE_BIT;
    return flags;
}

// The source side of a barrier only needs to make writes available.
constexpr VkAccessFlags WRITE_ACCESS = VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT |
                                       VK_ACCESS_HOST_WRITE_BIT | VK_ACCESS_MEMORY_WRITE_BIT;

VkDescriptorType ToVk(DescriptorType type)
{
    switch (type)
    {
    case DescriptorType::SAMPLED_TEXTURE:
        return VK_DESCRIPTOR_TYPE_SAMPLED_IMAGE;
    case DescriptorType::STORAGE_TEXTURE:
        return VK_DESCRIPTOR_TYPE_STORAGE_IMAGE;
    case DescriptorType::BUFFER:
    case DescriptorType::STORAGE_BUFFER:
        return VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    case DescriptorType::UNIFORM_BUFFER:
        return VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER;
    case DescriptorType::SAMPLER:
        return VK_DESCRIPTOR_TYPE_SAMPLER;
    default:
        return VK_DESCRIPTOR_TYPE_MAX_ENUM;
    }
}

class DeviceVK final : public Device
{
public:
    explicit DeviceVK(const DeviceVulkanDesc& desc) : m_Vk(desc)
    {
    }

    Result Initialize();
    ~DeviceVK() override;

    const DeviceDesc& GetDesc() const override
    {
        return m_Desc;
    }
    bool IsTextureFormatSupported(Format format, uint32_t usage) const override;

    Result CreateTexture(const TextureDesc& desc, Texture*& out) override;
    Result WrapTexture(const TextureVulkanDesc& desc, Texture*& out);
    void DestroyTexture(Texture* texture) override;
    Result CreateBuffer(const BufferDesc& desc, Buffer*& out) override;
    void DestroyBuffer(Buffer* buffer) override;
    Result CreateSampler(const SamplerDesc& desc, Sampler*& out) override;
    void DestroySampler(Sampler* sampler) override;

    const TextureDesc& GetTextureDesc(const Texture& texture) const override
    {
        return To(texture).desc;
    }
    const BufferDesc& GetBufferDesc(const Buffer& buffer) const override
    {
        return To(buffer).desc;
    }
    uint64_t GetTextureMemorySize(const Texture& texture) const override
    {
        return To(texture).memorySize;
    }
    uint64_t GetBufferMemorySize(const Buffer& buffer) const override
    {
        return To(buffer).memorySize;
    }
    void* MapBuffer(Buffer& buffer) override
    {
        return To(buffer).mapped;
    }

    Result CreateComputePipeline(const ComputePipelineDesc& desc, Pipeline*& out) override;
    void DestroyPipeline(Pipeline* pipeline) override;

    Result CreateDescriptorPool(const DescriptorPoolDesc& desc, DescriptorPool*& out) override;
    void DestroyDescriptorPool(DescriptorPool* pool) override;
    Result ResetDescriptorPool(DescriptorPool& pool) override;
    Result AllocateDescriptorSet(DescriptorPool& pool, const Pipeline& pipeline, uint32_t setIndex,
                                 DescriptorSet*& out) override;
    void UpdateDescriptorSet(DescriptorSet& set, const DescriptorWrite* writes, uint32_t writesNum) override;

    Result CreateQueryPool(uint32_t queryNum, QueryPool*& out) override;
    void DestroyQueryPool(QueryPool* pool) override;
    Result GetTimestamps(QueryPool& pool, uint32_t first, uint32_t num, uint64_t* outTicks) override;

    Result CreateCommandBuffer(CommandBuffer*& out) override;
    void DestroyCommandBuffer(CommandBuffer* commandBuffer) override;
    Result BeginCommandBuffer(CommandBuffer& commandBuffer) override;
    Result EndCommandBuffer(CommandBuffer& commandBuffer) override;
    Result SubmitAndWait(CommandBuffer& commandBuffer) override;
    Result WaitIdle() override;

    void CmdBarrier(CommandBuffer& cmd, const BarrierDesc& desc) override;
    void CmdBindPipeline(CommandBuffer& cmd, const Pipeline& pipeline) override;
    void CmdBindDescriptorSet(CommandBuffer& cmd, const Pipeline& pipeline, uint32_t setIndex,
                              const DescriptorSet& set) override;
    void CmdPushConstants(CommandBuffer& cmd, const Pipeline& pipeline, const void* data, uint32_t size) override;
    void CmdDispatch(CommandBuffer& cmd, uint32_t x, uint32_t y, uint32_t z) override;
    void CmdDispatchIndirect(CommandBuffer& cmd, const Buffer& buffer, uint64_t offset) override;
    void CmdClearTexture(CommandBuffer& cmd, Texture& texture, Layout layout, const float color[4]) override;
    void CmdFillBuffer(CommandBuffer& cmd, Buffer& buffer, uint64_t offset, uint64_t size, uint32_t value) override;
    void CmdCopyBuffer(CommandBuffer& cmd, Buffer& dst, uint64_t dstOffset, const Buffer& src, uint64_t srcOffset,
                       uint64_t size) override;
    void CmdCopyBufferToTexture(CommandBuffer& cmd, Texture& dst, const Buffer& src, uint64_t srcOffset) override;
    void CmdCopyTextureToBuffer(CommandBuffer& cmd, Buffer& dst, uint64_t dstOffset, const Texture& src) override;
    void CmdResetQueries(CommandBuffer& cmd, QueryPool& pool, uint32_t first, uint32_t num) override;
    void CmdWriteTimestamp(CommandBuffer& cmd, QueryPool& pool, uint32_t query) override;
    void CmdBeginLabel(CommandBuffer& cmd, const char* name) override;
    void CmdEndLabel(CommandBuffer& cmd) override;

private:
    void SetName(VkObjectType type, uint64_t handle, const char* name);
    bool FindMemoryType(uint32_t typeBits, MemoryLocation location, uint32_t& outIndex) const;
    Result AllocateMemory(const VkMemoryRequirements& requirements, MemoryLocation location, VkDeviceMemory& out);

    DeviceVulkanDesc m_Vk = {};
    DeviceDesc m_Desc = {};
    std::string m_AdapterName;
    VkPhysicalDeviceMemoryProperties m_MemoryProperties = {};
    VkCommandPool m_CommandPool = VK_NULL_HANDLE; // Only with a queue.
    VkFence m_Fence = VK_NULL_HANDLE;             // SubmitAndWait.
    uint64_t m_TimestampMask = ~0ull;             // timestampValidBits of the queue family.
    PFN_vkSetDebugUtilsObjectNameEXT m_SetObjectName = nullptr; // Null without VK_EXT_debug_utils.
    PFN_vkCmdBeginDebugUtilsLabelEXT m_CmdBeginLabel = nullptr;
    PFN_vkCmdEndDebugUtilsLabelEXT m_CmdEndLabel = nullptr;
};

Result DeviceVK::Initialize()
{
    if (!m_Vk.physicalDevice || !m_Vk.device)
        return Result::INVALID_ARGUMENT;

    VkPhysicalDeviceProperties properties = {};
    vkGetPhysicalDeviceProperties(m_Vk.physicalDevice, &properties);
    vkGetPhysicalDeviceMemoryProperties(m_Vk.physicalDevice, &m_MemoryProperties);

    uint32_t familyNum = 0;
    vkGetPhysicalDeviceQueueFamilyProperties(m_Vk.physicalDevice, &familyNum, nullptr);
    std::vector<VkQueueFamilyProperties> families(familyNum);
    vkGetPhysicalDeviceQueueFamilyProperties(m_Vk.physicalDevice, &familyNum, families.data());
    if (m_Vk.queueFamilyIndex >= familyNum || !(families[m_Vk.queueFamilyIndex].queueFlags & VK_QUEUE_COMPUTE_BIT))
        return Result::INVALID_ARGUMENT;

    m_AdapterName = properties.deviceName;
    m_Desc.adapterName = m_AdapterName.c_str();
    m_Desc.isSoftware = properties.deviceType == VK_PHYSICAL_DEVICE_TYPE_CPU;
    m_Desc.timestampsSupported = families[m_Vk.queueFamilyIndex].timestampValidBits != 0 &&
                                 properties.limits.timestampPeriod > 0.0f;
    m_Desc.timestampPeriodNs = properties.limits.timestampPeriod;
    uint32_t validBits = families[m_Vk.queueFamilyIndex].timestampValidBits;
    m_TimestampMask = validBits >= 64 ? ~0ull : (1ull << validBits) - 1;
    m_Desc.storageTextureReadWithoutFormat = m_Vk.storageImageReadWithoutFormatEnabled;
    m_Desc.storageTextureWriteWithoutFormat = m_Vk.storageImageWriteWithoutFormatEnabled;
    m_Desc.uniformBufferOffsetAlignment = properties.limits.minUniformBufferOffsetAlignment;
    m_Desc.storageBufferOffsetAlignment = properties.limits.minStorageBufferOffsetAlignment;
    m_Desc.uniformBufferMaxRange = properties.limits.maxUniformBufferRange;
    for (uint32_t i = 0; i < 3; i++)
        m_Desc.dispatchMaxNum[i] = properties.limits.maxComputeWorkGroupCount[i];

    if (m_Vk.instance)
    {
        m_SetObjectName = (PFN_vkSetDebugUtilsObjectNameEXT)vkGetInstanceProcAddr(m_Vk.instance,
                                                                                  "vkSetDebugUtilsObjectNameEXT");
        m_CmdBeginLabel = (PFN_vkCmdBeginDebugUtilsLabelEXT)vkGetInstanceProcAddr(m_Vk.instance,
                                                                                 "vkCmdBeginDebugUtilsLabelEXT");
        m_CmdEndLabel = (PFN_vkCmdEndDebugUtilsLabelEXT)vkGetInstanceProcAddr(m_Vk.instance,
                                                                             "vkCmdEndDebugUtilsLabelEXT");
    }

    if (m_Vk.queue)
    {
        VkCommandPoolCreateInfo poolInfo = {VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
        poolInfo.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
        poolInfo.queueFamilyIndex = m_Vk.queueFamilyIndex;
        VkResult result = vkCreateCommandPool(m_Vk.device, &poolInfo, m_Vk.allocationCallbacks, &m_CommandPool);
        if (result != VK_SUCCESS)
            return FromVk(result);

        VkFenceCreateInfo fenceInfo = {VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
        result = vkCreateFence(m_Vk.device, &fenceInfo, m_Vk.allocationCallbacks, &m_Fence);
        if (result != VK_SUCCESS)
            return FromVk(result);
    }

    return Result::SUCCESS;
}

DeviceVK::~DeviceVK()
{
    if (m_Fence)
        vkDestroyFence(m_Vk.device, m_Fence, m_Vk.allocationCallbacks);
    if (m_CommandPool)
        vkDestroyCommandPool(m_Vk.device, m_CommandPool, m_Vk.allocationCallbacks);
}

void DeviceVK::SetName(VkObjectType type, uint64_t handle, const char* name)
{
    if (!m_SetObjectName || !name || !handle)
        return;
    VkDebugUtilsObjectNameInfoEXT info = {VK_STRUCTURE_TYPE_DEBUG_UTILS_OBJECT_NAME_INFO_EXT};
    info.objectType = type;
    info.objectHandle = handle;
    info.pObjectName = name;
    m_SetObjectName(m_Vk.device, &info);
}

bool DeviceVK::FindMemoryType(uint32_t typeBits, MemoryLocation location, uint32_t& outIndex) const
{
    // Preferred flags first, then the minimum that works.
    VkMemoryPropertyFlags candidates[2] = {};
    switch (location)
    {
    case MemoryLocation::DEVICE:
        candidates[0] = candidates[1] = VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT;
        break;
    case MemoryLocation::HOST_UPLOAD:
        candidates[0] = candidates[1] = VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
        break;
    case MemoryLocation::HOST_READBACK:
        candidates[0] = VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT |
                        VK_MEMORY_PROPERTY_HOST_CACHED_BIT;
        candidates[1] = VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
        break;
    }
    for (VkMemoryPropertyFlags flags : candidates)
    {
        for (uint32_t i = 0; i < m_MemoryProperties.memoryTypeCount; i++)
        {
            if ((typeBits & (1u << i)) && (m_MemoryProperties.memoryTypes[i].propertyFlags & flags) == flags)
            {
                outIndex = i;
                return true;
            }
        }
    }
    return false;
}

Result DeviceVK::AllocateMemory(const VkMemoryRequirements& requirements, MemoryLocation location,
                                VkDeviceMemory& out)
{
    VkMemoryAllocateInfo info = {VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
    info.allocationSize = requirements.size;
    if (!FindMemoryType(requirements.memoryTypeBits, location, info.memoryTypeIndex))
        return Result::UNSUPPORTED;
    return FromVk(vkAllocateMemory(m_Vk.device, &info, m_Vk.allocationCallbacks, &out));
}

bool DeviceVK::IsTextureFormatSupported(Format format, uint32_t usage) const
{
    VkFormat vkFormat = ToVkFormat(format);
    if (vkFormat == VK_FORMAT_UNDEFINED)
        return false;
    VkFormatProperties properties = {};
    vkGetPhysicalDeviceFormatProperties(m_Vk.physicalDevice, vkFormat, &properties);
    VkFormatFeatureFlags needed = 0;
    if (usage & TEXTURE_USAGE_SAMPLED)
        needed |= VK_FORMAT_FEATURE_SAMPLED_IMAGE_BIT;
    if (usage & TEXTURE_USAGE_STORAGE)
        needed |= VK_FORMAT_FEATURE_STORAGE_IMAGE_BIT;
    if (usage & TEXTURE_USAGE_COPY_SOURCE)
        needed |= VK_FORMAT_FEATURE_TRANSFER_SRC_BIT;
    if (usage & TEXTURE_USAGE_COPY_DESTINATION)
        needed |= VK_FORMAT_FEATURE_TRANSFER_DST_BIT;
    return (properties.optimalTilingFeatures & needed) == needed;
}

Result DeviceVK::CreateTexture(const TextureDesc& desc, Texture*& out)
{
    out = nullptr;
    VkFormat vkFormat = ToVkFormat(desc.format);
    if (vkFormat == VK_FORMAT_UNDEFINED || !desc.width || !desc.height || !desc.usage)
        return Result::INVALID_ARGUMENT;
    if (!IsTextureFormatSupported(desc.format, desc.usage))
        return Result::UNSUPPORTED;

    TextureVK* texture = new (std::nothrow) TextureVK();
    if (!texture)
        return Result::OUT_OF_MEMORY;
    texture->name = desc.name ? desc.name : "";
    texture->desc = desc;
    texture->desc.name = texture->name.c_str();
    texture->vkFormat = vkFormat;

    VkImageCreateInfo imageInfo = {VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO};
    imageInfo.imageType = VK_IMAGE_TYPE_2D;
    imageInfo.format = vkFormat;
    imageInfo.extent = {desc.width, desc.height, 1};
    imageInfo.mipLevels = 1;
    imageInfo.arrayLayers = 1;
    imageInfo.samples = VK_SAMPLE_COUNT_1_BIT;
    imageInfo.tiling = VK_IMAGE_TILING_OPTIMAL;
    if (desc.usage & TEXTURE_USAGE_SAMPLED)
        imageInfo.usage |= VK_IMAGE_USAGE_SAMPLED_BIT;
    if (desc.usage & TEXTURE_USAGE_STORAGE)
        imageInfo.usage |= VK_IMAGE_USAGE_STORAGE_BIT;
    if (desc.usage & TEXTURE_USAGE_COPY_SOURCE)
        imageInfo.usage |= VK_IMAGE_USAGE_TRANSFER_SRC_BIT;
    if (desc.usage & TEXTURE_USAGE_COPY_DESTINATION)
        imageInfo.usage |= VK_IMAGE_USAGE_TRANSFER_DST_BIT;
    imageInfo.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
    imageInfo.initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;

    Result result = FromVk(vkCreateImage(m_Vk.device, &imageInfo, m_Vk.allocationCallbacks, &texture->image));
    if (result == Result::SUCCESS)
    {
        VkMemoryRequirements requirements = {};
        vkGetImageMemoryRequirements(m_Vk.device, texture->image, &requirements);
        texture->memorySize = requirements.size;
        result = AllocateMemory(requirements, MemoryLocation::DEVICE, texture->memory);
    }
    if (result == Result::SUCCESS)
        result = FromVk(vkBindImageMemory(m_Vk.device, texture->image, texture->memory, 0));
    if (result == Result::SUCCESS)
    {
        VkImageViewCreateInfo viewInfo = {VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
        viewInfo.image = texture->image;
        viewInfo.viewType = VK_IMAGE_VIEW_TYPE_2D;
        viewInfo.format = vkFormat;
        viewInfo.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
        result = FromVk(vkCreateImageView(m_Vk.device, &viewInfo, m_Vk.allocationCallbacks, &texture->view));
    }
    if (result != Result::SUCCESS)
    {
        DestroyTexture(From<Texture>(texture));
        return result;
    }

    SetName(VK_OBJECT_TYPE_IMAGE, (uint64_t)texture->image, desc.name);
    SetName(VK_OBJECT_TYPE_IMAGE_VIEW, (uint64_t)texture->view, desc.name);
    out = From<Texture>(texture);
    return Result::SUCCESS;
}

Result DeviceVK::WrapTexture(const TextureVulkanDesc& desc, Texture*& out)
{
    out = nullptr;
    if (!desc.image || !desc.view)
        return Result::INVALID_ARGUMENT;
    TextureVK* texture = new (std::nothrow) TextureVK();
    if (!texture)
        return Result::OUT_OF_MEMORY;
    texture->image = desc.image;
    texture->view = desc.view;
    texture->vkFormat = desc.format;
    texture->desc.format = FromVkFormat(desc.format);
    texture->desc.width = desc.width;
    texture->desc.height = desc.height;
    texture->desc.usage = desc.usage;
    texture->desc.name = texture->name.c_str();
    out = From<Texture>(texture);
    return Result::SUCCESS;
}

void DeviceVK::DestroyTexture(Texture* texture)
{
    if (!texture)
        return;
    TextureVK* t = &To(*texture);
    if (t->memory) // Owned (not wrapped).
    {
        vkDestroyImageView(m_Vk.device, t->view, m_Vk.allocationCallbacks);
        vkDestroyImage(m_Vk.device, t->image, m_Vk.allocationCallbacks);
        vkFreeMemory(m_Vk.device, t->memory, m_Vk.allocationCallbacks);
    }
    delete t;
}

Result DeviceVK::CreateBuffer(const BufferDesc& desc, Buffer*& out)
{
    out = nullptr;
    if (!desc.size || !desc.usage)
        return Result::INVALID_ARGUMENT;

    BufferVK* buffer = new (std::nothrow) BufferVK();
    if (!buffer)
        return Result::OUT_OF_MEMORY;
    buffer->name = desc.name ? desc.name : "";
    buffer->desc = desc;
    buffer->desc.name = buffer->name.c_str();

    VkBufferCreateInfo bufferInfo = {VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
    bufferInfo.size = desc.size;
    if (desc.usage & BUFFER_USAGE_STORAGE)
        bufferInfo.usage |= VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;
    if (desc.usage & BUFFER_USAGE_UNIFORM)
        bufferInfo.usage |= VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT;
    if (desc.usage & BUFFER_USAGE_INDIRECT_ARGUMENTS)
        bufferInfo.usage |= VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT;
    if (desc.usage & BUFFER_USAGE_COPY_SOURCE)
        bufferInfo.usage |= VK_BUFFER_USAGE_TRANSFER_SRC_BIT;
    if (desc.usage & BUFFER_USAGE_COPY_DESTINATION)
        bufferInfo.usage |= VK_BUFFER_USAGE_TRANSFER_DST_BIT;
    bufferInfo.sharingMode = VK_SHARING_MODE_EXCLUSIVE;

    Result result = FromVk(vkCreateBuffer(m_Vk.device, &bufferInfo, m_Vk.allocationCallbacks, &buffer->buffer));
    if (result == Result::SUCCESS)
    {
        VkMemoryRequirements requirements = {};
        vkGetBufferMemoryRequirements(m_Vk.device, buffer->buffer, &requirements);
        buffer->memorySize = requirements.size;
        result = AllocateMemory(requirements, desc.location, buffer->memory);
    }
    if (result == Result::SUCCESS)
        result = FromVk(vkBindBufferMemory(m_Vk.device, buffer->buffer, buffer->memory, 0));
    if (result == Result::SUCCESS && desc.location != MemoryLocation::DEVICE)
        result = FromVk(vkMapMemory(m_Vk.device, buffer->memory, 0, VK_WHOLE_SIZE, 0, &buffer->mapped));
    if (result != Result::SUCCESS)
    {
        DestroyBuffer(From<Buffer>(buffer));
        return result;
    }

    SetName(VK_OBJECT_TYPE_BUFFER, (uint64_t)buffer->buffer, desc.name);
    out = From<Buffer>(buffer);
    return Result::SUCCESS;
}

void DeviceVK::DestroyBuffer(Buffer* buffer)
{
    if (!buffer)
        return;
    BufferVK* b = &To(*buffer);
    if (b->buffer)
        vkDestroyBuffer(m_Vk.device, b->buffer, m_Vk.allocationCallbacks);
    if (b->memory)
        vkFreeMemory(m_Vk.device, b->memory, m_Vk.allocationCallbacks); // Unmaps implicitly.
    delete b;
}

Result DeviceVK::CreateSampler(const SamplerDesc& desc, Sampler*& out)
{
    out = nullptr;
    VkSamplerCreateInfo info = {VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO};
    info.magFilter = info.minFilter = desc.filter == Filter::LINEAR ? VK_FILTER_LINEAR : VK_FILTER_NEAREST;
    info.mipmapMode = VK_SAMPLER_MIPMAP_MODE_NEAREST;
    VkSamplerAddressMode mode = desc.addressMode == AddressMode::REPEAT            ? VK_SAMPLER_ADDRESS_MODE_REPEAT
                                : desc.addressMode == AddressMode::MIRRORED_REPEAT ? VK_SAMPLER_ADDRESS_MODE_MIRRORED_REPEAT
                                                                                   : VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE;
    info.addressModeU = info.addressModeV = info.addressModeW = mode;
    info.maxLod = 0.0f;
    info.borderColor = VK_BORDER_COLOR_FLOAT_TRANSPARENT_BLACK;

    SamplerVK* sampler = new (std::nothrow) SamplerVK();
    if (!sampler)
        return Result::OUT_OF_MEMORY;
    Result result = FromVk(vkCreateSampler(m_Vk.device, &info, m_Vk.allocationCallbacks, &sampler->sampler));
    if (result != Result::SUCCESS)
    {
        delete sampler;
        return result;
    }
    out = From<Sampler>(sampler);
    return Result::SUCCESS;
}

void DeviceVK::DestroySampler(Sampler* sampler)
{
    if (!sampler)
        return;
    vkDestroySampler(m_Vk.device, To(*sampler).sampler, m_Vk.allocationCallbacks);
    delete &To(*sampler);
}

Result DeviceVK::CreateComputePipeline(const ComputePipelineDesc& desc, Pipeline*& out)
{
    out = nullptr;
    if (!desc.spirv || !desc.spirvSize || desc.spirvSize % 4 || (desc.setsNum && !desc.sets))
        return Result::INVALID_ARGUMENT;

    PipelineVK* pipeline = new (std::nothrow) PipelineVK();
    if (!pipeline)
        return Result::OUT_OF_MEMORY;
    Result result = Result::SUCCESS;

    // Set layouts, one per DescriptorSetDesc.
    for (uint32_t s = 0; s < desc.setsNum && result == Result::SUCCESS; s++)
    {
        const DescriptorSetDesc& set = desc.sets[s];
        std::vector<VkDescriptorSetLayoutBinding> bindings(set.bindingsNum);
        std::vector<std::vector<VkSampler>> immutable(set.bindingsNum);
        for (uint32_t b = 0; b < set.bindingsNum; b++)
        {
            const DescriptorBindingDesc& binding = set.bindings[b];
            bindings[b].binding = binding.binding;
            bindings[b].descriptorType = ToVk(binding.type);
            bindings[b].descriptorCount = binding.count;
            bindings[b].stageFlags = VK_SHADER_STAGE_COMPUTE_BIT;
            if (bindings[b].descriptorType == VK_DESCRIPTOR_TYPE_MAX_ENUM)
                result = Result::INVALID_ARGUMENT;
            if (binding.type == DescriptorType::SAMPLER && binding.immutableSamplers)
            {
                for (uint32_t i = 0; i < binding.count; i++)
                    immutable[b].push_back(To(*binding.immutableSamplers[i]).sampler);
                bindings[b].pImmutableSamplers = immutable[b].data();
            }
        }
        VkDescriptorSetLayoutCreateInfo layoutInfo = {VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
        layoutInfo.bindingCount = set.bindingsNum;
        layoutInfo.pBindings = bindings.data();
        VkDescriptorSetLayout layout = VK_NULL_HANDLE;
        if (result == Result::SUCCESS)
            result = FromVk(vkCreateDescriptorSetLayout(m_Vk.device, &layoutInfo, m_Vk.allocationCallbacks, &layout));
        if (result == Result::SUCCESS)
            pipeline->setLayouts.push_back(layout);
    }

    if (result == Result::SUCCESS)
    {
        VkPushConstantRange pushRange = {VK_SHADER_STAGE_COMPUTE_BIT, 0, desc.pushConstantsSize};
        VkPipelineLayoutCreateInfo layoutInfo = {VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
        layoutInfo.setLayoutCount = (uint32_t)pipeline->setLayouts.size();
        layoutInfo.pSetLayouts = pipeline->setLayouts.data();
        layoutInfo.pushConstantRangeCount = desc.pushConstantsSize ? 1 : 0;
        layoutInfo.pPushConstantRanges = &pushRange;
        result = FromVk(vkCreatePipelineLayout(m_Vk.device, &layoutInfo, m_Vk.allocationCallbacks, &pipeline->layout));
    }

    VkShaderModule module = VK_NULL_HANDLE;
    if (result == Result::SUCCESS)
    {
        // Copy: SPIR-V must be 4-byte aligned, the caller's pointer need not be.
        std::vector<uint32_t> words((size_t)desc.spirvSize / 4);
        std::memcpy(words.data(), desc.spirv, (size_t)desc.spirvSize);
        VkShaderModuleCreateInfo moduleInfo = {VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
        moduleInfo.codeSize = (size_t)desc.spirvSize;
        moduleInfo.pCode = words.data();
        result = FromVk(vkCreateShaderModule(m_Vk.device, &moduleInfo, m_Vk.allocationCallbacks, &module));
    }

    if (result == Result::SUCCESS)
    {
        VkComputePipelineCreateInfo pipelineInfo = {VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO};
        pipelineInfo.stage.sType = VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO;
        pipelineInfo.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
        pipelineInfo.stage.module = module;
        pipelineInfo.stage.pName = desc.entryPoint ? desc.entryPoint : "main";
        pipelineInfo.layout = pipeline->layout;
        result = FromVk(vkCreateComputePipelines(m_Vk.device, VK_NULL_HANDLE, 1, &pipelineInfo,
                                                 m_Vk.allocationCallbacks, &pipeline->pipeline));
    }
    if (module)
        vkDestroyShaderModule(m_Vk.device, module, m_Vk.allocationCallbacks);

    if (result != Result::SUCCESS)
    {
        DestroyPipeline(From<Pipeline>(pipeline));
        return result;
    }
    SetName(VK_OBJECT_TYPE_PIPELINE, (uint64_t)pipeline->pipeline, desc.name);
    out = From<Pipeline>(pipeline);
    return Result::SUCCESS;
}

void DeviceVK::DestroyPipeline(Pipeline* pipeline)
{
    if (!pipeline)
        return;
    PipelineVK* p = &To(*pipeline);
    if (p->pipeline)
        vkDestroyPipeline(m_Vk.device, p->pipeline, m_Vk.allocationCallbacks);
    if (p->layout)
        vkDestroyPipelineLayout(m_Vk.device, p->layout, m_Vk.allocationCallbacks);
    for (VkDescriptorSetLayout layout : p->setLayouts)
        vkDestroyDescriptorSetLayout(m_Vk.device, layout, m_Vk.allocationCallbacks);
    delete p;
}

Result DeviceVK::CreateDescriptorPool(const DescriptorPoolDesc& desc, DescriptorPool*& out)
{
    out = nullptr;
    if (!desc.setsMaxNum)
        return Result::INVALID_ARGUMENT;

    // BUFFER and STORAGE_BUFFER are both VK_DESCRIPTOR_TYPE_STORAGE_BUFFER: merge them.
    std::vector<VkDescriptorPoolSize> sizes;
    for (uint32_t t = 0; t < (uint32_t)DescriptorType::MAX_NUM; t++)
    {
        uint32_t num = desc.descriptorsMaxNum[t];
        VkDescriptorType vkType = ToVk((DescriptorType)t);
        if (!num)
            continue;
        bool merged = false;
        for (VkDescriptorPoolSize& size : sizes)
        {
            if (size.type == vkType)
            {
                size.descriptorCount += num;
                merged = true;
            }
        }
        if (!merged)
            sizes.push_back({vkType, num});
    }

    DescriptorPoolVK* pool = new (std::nothrow) DescriptorPoolVK();
    if (!pool)
        return Result::OUT_OF_MEMORY;
    VkDescriptorPoolCreateInfo info = {VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
    info.maxSets = desc.setsMaxNum;
    info.poolSizeCount = (uint32_t)sizes.size();
    info.pPoolSizes = sizes.data();
    Result result = FromVk(vkCreateDescriptorPool(m_Vk.device, &info, m_Vk.allocationCallbacks, &pool->pool));
    if (result != Result::SUCCESS)
    {
        delete pool;
        return result;
    }
    pool->sets.reserve(desc.setsMaxNum);
    out = From<DescriptorPool>(pool);
    return Result::SUCCESS;
}

void DeviceVK::DestroyDescriptorPool(DescriptorPool* pool)
{
    if (!pool)
        return;
    vkDestroyDescriptorPool(m_Vk.device, To(*pool).pool, m_Vk.allocationCallbacks);
    delete &To(*pool);
}

Result DeviceVK::ResetDescriptorPool(DescriptorPool& pool)
{
    To(pool).sets.clear();
    return FromVk(vkResetDescriptorPool(m_Vk.device, To(pool).pool, 0));
}

Result DeviceVK::AllocateDescriptorSet(DescriptorPool& pool, const Pipeline& pipeline, uint32_t setIndex,
                                       DescriptorSet*& out)
{
    out = nullptr;
    DescriptorPoolVK& p = To(pool);
    const PipelineVK& pipe = To(pipeline);
    if (setIndex >= pipe.setLayouts.size())
        return Result::INVALID_ARGUMENT;
    if (p.sets.size() == p.sets.capacity()) // Never reallocate: handed-out pointers must stay valid.
        return Result::OUT_OF_MEMORY;

    VkDescriptorSetAllocateInfo info = {VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
    info.descriptorPool = p.pool;
    info.descriptorSetCount = 1;
    info.pSetLayouts = &pipe.setLayouts[setIndex];
    DescriptorSetVK set = {};
    Result result = FromVk(vkAllocateDescriptorSets(m_Vk.device, &info, &set.set));
    if (result != Result::SUCCESS)
        return result;
    p.sets.push_back(set);
    out = From<DescriptorSet>(&p.sets.back());
    return Result::SUCCESS;
}

void DeviceVK::UpdateDescriptorSet(DescriptorSet& set, const DescriptorWrite* writes, uint32_t writesNum)
{
    std::vector<VkWriteDescriptorSet> vkWrites(writesNum);
    std::vector<VkDescriptorImageInfo> images(writesNum);
    std::vector<VkDescriptorBufferInfo> buffers(writesNum);
    for (uint32_t i = 0; i < writesNum; i++)
    {
        const DescriptorWrite& w = writes[i];
        VkWriteDescriptorSet& vk = vkWrites[i];
        vk = {VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
        vk.dstSet = To(set).set;
        vk.dstBinding = w.binding;
        vk.dstArrayElement = w.arrayElement;
        vk.descriptorCount = 1;
        vk.descriptorType = ToVk(w.type);
        switch (w.type)
        {
        case DescriptorType::SAMPLED_TEXTURE:
            images[i] = {VK_NULL_HANDLE, To(*w.texture).view, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL};
            vk.pImageInfo = &images[i];
            break;
        case DescriptorType::STORAGE_TEXTURE:
            images[i] = {VK_NULL_HANDLE, To(*w.texture).view, VK_IMAGE_LAYOUT_GENERAL};
            vk.pImageInfo = &images[i];
            break;
        case DescriptorType::SAMPLER:
            images[i] = {To(*w.sampler).sampler, VK_NULL_HANDLE, VK_IMAGE_LAYOUT_UNDEFINED};
            vk.pImageInfo = &images[i];
            break;
        default:
            buffers[i] = {To(*w.buffer).buffer, w.offset, w.range ? w.range : VK_WHOLE_SIZE};
            vk.pBufferInfo = &buffers[i];
            break;
        }
    }
    vkUpdateDescriptorSets(m_Vk.device, writesNum, vkWrites.data(), 0, nullptr);
}

Result DeviceVK::CreateQueryPool(uint32_t queryNum, QueryPool*& out)
{
    out = nullptr;
    if (!queryNum)
        return Result::INVALID_ARGUMENT;
    if (!m_Desc.timestampsSupported)
        return Result::UNSUPPORTED;
    QueryPoolVK* pool = new (std::nothrow) QueryPoolVK();
    if (!pool)
        return Result::OUT_OF_MEMORY;
    VkQueryPoolCreateInfo info = {VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
    info.queryType = VK_QUERY_TYPE_TIMESTAMP;
    info.queryCount = queryNum;
    Result result = FromVk(vkCreateQueryPool(m_Vk.device, &info, m_Vk.allocationCallbacks, &pool->pool));
    if (result != Result::SUCCESS)
    {
        delete pool;
        return result;
    }
    pool->queryNum = queryNum;
    out = From<QueryPool>(pool);
    return Result::SUCCESS;
}

void DeviceVK::DestroyQueryPool(QueryPool* pool)
{
    if (!pool)
        return;
    vkDestroyQueryPool(m_Vk.device, To(*pool).pool, m_Vk.allocationCallbacks);
    delete &To(*pool);
}

Result DeviceVK::GetTimestamps(QueryPool& pool, uint32_t first, uint32_t num, uint64_t* outTicks)
{
    if (!num || first + num > To(pool).queryNum || !outTicks)
        return Result::INVALID_ARGUMENT;
    VkResult result = vkGetQueryPoolResults(m_Vk.device, To(pool).pool, first, num, num * sizeof(uint64_t), outTicks,
                                            sizeof(uint64_t), VK_QUERY_RESULT_64_BIT);
    for (uint32_t i = 0; i < num && result == VK_SUCCESS; i++)
        outTicks[i] &= m_TimestampMask;
    return FromVk(result);
}

Result DeviceVK::CreateCommandBuffer(CommandBuffer*& out)
{
    out = nullptr;
    if (!m_CommandPool)
        return Result::UNSUPPORTED;
    VkCommandBufferAllocateInfo info = {VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
    info.commandPool = m_CommandPool;
    info.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
    info.commandBufferCount = 1;
    VkCommandBuffer vkCmd = VK_NULL_HANDLE;
    Result result = FromVk(vkAllocateCommandBuffers(m_Vk.device, &info, &vkCmd));
    if (result == Result::SUCCESS)
        out = &GetCommandBuffer(vkCmd);
    return result;
}

void DeviceVK::DestroyCommandBuffer(CommandBuffer* commandBuffer)
{
    if (!commandBuffer || !m_CommandPool)
        return;
    VkCommandBuffer vkCmd = ToVk(*commandBuffer);
    vkFreeCommandBuffers(m_Vk.device, m_CommandPool, 1, &vkCmd);
}

Result DeviceVK::BeginCommandBuffer(CommandBuffer& commandBuffer)
{
    VkCommandBufferBeginInfo info = {VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
    info.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
    return FromVk(vkBeginCommandBuffer(ToVk(commandBuffer), &info)); // Implicit reset (pool flag).
}

Result DeviceVK::EndCommandBuffer(CommandBuffer& commandBuffer)
{
    return FromVk(vkEndCommandBuffer(ToVk(commandBuffer)));
}

Result DeviceVK::SubmitAndWait(CommandBuffer& commandBuffer)
{
    if (!m_Vk.queue)
        return Result::UNSUPPORTED;
    VkCommandBuffer vkCmd = ToVk(commandBuffer);
    VkSubmitInfo submit = {VK_STRUCTURE_TYPE_SUBMIT_INFO};
    submit.commandBufferCount = 1;
    submit.pCommandBuffers = &vkCmd;
    Result result = FromVk(vkQueueSubmit(m_Vk.queue, 1, &submit, m_Fence));
    if (result != Result::SUCCESS)
        return result;
    result = FromVk(vkWaitForFences(m_Vk.device, 1, &m_Fence, VK_TRUE, UINT64_MAX));
    vkResetFences(m_Vk.device, 1, &m_Fence);
    return result;
}

Result DeviceVK::WaitIdle()
{
    if (!m_Vk.queue)
        return Result::UNSUPPORTED;
    return FromVk(vkQueueWaitIdle(m_Vk.queue));
}

void DeviceVK::CmdBarrier(CommandBuffer& cmd, const BarrierDesc& desc)
{
    VkPipelineStageFlags srcStages = 0;
    VkPipelineStageFlags dstStages = 0;

    std::vector<VkMemoryBarrier> globals(desc.globalsNum);
    for (uint32_t i = 0; i < desc.globalsNum; i++)
    {
        const GlobalBarrier& b = desc.globals[i];
        globals[i] = {VK_STRUCTURE_TYPE_MEMORY_BARRIER};
        globals[i].srcAccessMask = ToAccess(b.before) & WRITE_ACCESS;
        globals[i].dstAccessMask = ToAccess(b.after);
        srcStages |= ToStages(b.before);
        dstStages |= ToStages(b.after);
    }

    std::vector<VkBufferMemoryBarrier> buffers(desc.buffersNum);
    for (uint32_t i = 0; i < desc.buffersNum; i++)
    {
        const BufferBarrier& b = desc.buffers[i];
        buffers[i] = {VK_STRUCTURE_TYPE_BUFFER_MEMORY_BARRIER};
        buffers[i].srcAccessMask = ToAccess(b.before) & WRITE_ACCESS;
        buffers[i].dstAccessMask = ToAccess(b.after);
        buffers[i].srcQueueFamilyIndex = buffers[i].dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
        buffers[i].buffer = To(*b.buffer).buffer;
        buffers[i].size = VK_WHOLE_SIZE;
        srcStages |= ToStages(b.before);
        dstStages |= ToStages(b.after);
    }

    std::vector<VkImageMemoryBarrier> images(desc.texturesNum);
    for (uint32_t i = 0; i < desc.texturesNum; i++)
    {
        const TextureBarrier& b = desc.textures[i];
        images[i] = {VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER};
        images[i].srcAccessMask = ToAccess(b.before.access) & WRITE_ACCESS;
        images[i].dstAccessMask = ToAccess(b.after.access);
        images[i].oldLayout = ToVkImageLayout(b.before.layout);
        images[i].newLayout = ToVkImageLayout(b.after.layout);
        images[i].srcQueueFamilyIndex = images[i].dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
        images[i].image = To(*b.texture).image;
        images[i].subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
        srcStages |= ToStages(b.before.access);
        dstStages |= ToStages(b.after.access);
    }

    if (!srcStages)
        srcStages = VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT; // Nothing to wait for (first use).
    if (!dstStages)
        dstStages = VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT;
    vkCmdPipelineBarrier(ToVk(cmd), srcStages, dstStages, 0, desc.globalsNum, globals.data(), desc.buffersNum,
                         buffers.data(), desc.texturesNum, images.data());
}

void DeviceVK::CmdBindPipeline(CommandBuffer& cmd, const Pipeline& pipeline)
{
    vkCmdBindPipeline(ToVk(cmd), VK_PIPELINE_BIND_POINT_COMPUTE, To(pipeline).pipeline);
}

void DeviceVK::CmdBindDescriptorSet(CommandBuffer& cmd, const Pipeline& pipeline, uint32_t setIndex,
                                    const DescriptorSet& set)
{
    vkCmdBindDescriptorSets(ToVk(cmd), VK_PIPELINE_BIND_POINT_COMPUTE, To(pipeline).layout, setIndex, 1,
                            &To(set).set, 0, nullptr);
}

void DeviceVK::CmdPushConstants(CommandBuffer& cmd, const Pipeline& pipeline, const void* data, uint32_t size)
{
    vkCmdPushConstants(ToVk(cmd), To(pipeline).layout, VK_SHADER_STAGE_COMPUTE_BIT, 0, size, data);
}

void DeviceVK::CmdDispatch(CommandBuffer& cmd, uint32_t x, uint32_t y, uint32_t z)
{
    vkCmdDispatch(ToVk(cmd), x, y, z);
}

void DeviceVK::CmdDispatchIndirect(CommandBuffer& cmd, const Buffer& buffer, uint64_t offset)
{
    vkCmdDispatchIndirect(ToVk(cmd), To(buffer).buffer, offset);
}

void DeviceVK::CmdClearTexture(CommandBuffer& cmd, Texture& texture, Layout layout, const float color[4])
{
    VkClearColorValue value = {};
    bool isInteger = GetFormatInfo(To(texture).desc.format).isInteger;
    for (uint32_t i = 0; i < 4; i++)
    {
        if (isInteger)
            value.uint32[i] = color[i] > 0.0f ? (uint32_t)color[i] : 0;
        else
            value.float32[i] = color[i];
    }
    VkImageSubresourceRange range = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
    vkCmdClearColorImage(ToVk(cmd), To(texture).image, ToVkImageLayout(layout), &value, 1, &range);
}

void DeviceVK::CmdFillBuffer(CommandBuffer& cmd, Buffer& buffer, uint64_t offset, uint64_t size, uint32_t value)
{
    vkCmdFillBuffer(ToVk(cmd), To(buffer).buffer, offset, size ? size : VK_WHOLE_SIZE, value);
}

void DeviceVK::CmdCopyBuffer(CommandBuffer& cmd, Buffer& dst, uint64_t dstOffset, const Buffer& src,
                             uint64_t srcOffset, uint64_t size)
{
    VkBufferCopy region = {srcOffset, dstOffset, size};
    vkCmdCopyBuffer(ToVk(cmd), To(src).buffer, To(dst).buffer, 1, &region);
}

void DeviceVK::CmdCopyBufferToTexture(CommandBuffer& cmd, Texture& dst, const Buffer& src, uint64_t srcOffset)
{
    const TextureVK& t = To(dst);
    VkBufferImageCopy region = {};
    region.bufferOffset = srcOffset;
    region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
    region.imageExtent = {t.desc.width, t.desc.height, 1};
    vkCmdCopyBufferToImage(ToVk(cmd), To(src).buffer, t.image, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &region);
}

void DeviceVK::CmdCopyTextureToBuffer(CommandBuffer& cmd, Buffer& dst, uint64_t dstOffset, const Texture& src)
{
    const TextureVK& t = To(src);
    VkBufferImageCopy region = {};
    region.bufferOffset = dstOffset;
    region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
    region.imageExtent = {t.desc.width, t.desc.height, 1};
    vkCmdCopyImageToBuffer(ToVk(cmd), t.image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, To(dst).buffer, 1, &region);
}

void DeviceVK::CmdResetQueries(CommandBuffer& cmd, QueryPool& pool, uint32_t first, uint32_t num)
{
    vkCmdResetQueryPool(ToVk(cmd), To(pool).pool, first, num);
}

void DeviceVK::CmdWriteTimestamp(CommandBuffer& cmd, QueryPool& pool, uint32_t query)
{
    vkCmdWriteTimestamp(ToVk(cmd), VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, To(pool).pool, query);
}

void DeviceVK::CmdBeginLabel(CommandBuffer& cmd, const char* name)
{
    if (!m_CmdBeginLabel)
        return;
    VkDebugUtilsLabelEXT label = {VK_STRUCTURE_TYPE_DEBUG_UTILS_LABEL_EXT};
    label.pLabelName = name ? name : "";
    m_CmdBeginLabel(ToVk(cmd), &label);
}

void DeviceVK::CmdEndLabel(CommandBuffer& cmd)
{
    if (m_CmdEndLabel)
        m_CmdEndLabel(ToVk(cmd));
}

} // namespace

Result CreateDeviceVulkan(const DeviceVulkanDesc& desc, Device*& out)
{
    out = nullptr;
    DeviceVK* device = new (std::nothrow) DeviceVK(desc);
    if (!device)
        return Result::OUT_OF_MEMORY;
    Result result = device->Initialize();
    if (result != Result::SUCCESS)
    {
        delete device;
        return result;
    }
    out = device;
    return Result::SUCCESS;
}

Result WrapTextureVulkan(Device& device, const TextureVulkanDesc& desc, Texture*& out)
{
    return static_cast<DeviceVK&>(device).WrapTexture(desc, out);
}

VkImage GetVkImage(const Texture& texture)
{
    return To(texture).image;
}

VkImageView GetVkImageView(const Texture& texture)
{
    return To(texture).view;
}

VkBuffer GetVkBuffer(const Buffer& buffer)
{
    return To(buffer).buffer;
}

namespace
{
struct FormatPair
{
    Format format;
    VkFormat vkFormat;
};
constexpr FormatPair FORMATS[] = {
    {Format::UNKNOWN, VK_FORMAT_UNDEFINED},
    {Format::R8_UNORM, VK_FORMAT_R8_UNORM},
    {Format::RG8_UNORM, VK_FORMAT_R8G8_UNORM},
    {Format::RGBA8_UNORM, VK_FORMAT_R8G8B8A8_UNORM},
    {Format::RGBA8_SRGB, VK_FORMAT_R8G8B8A8_SRGB},
    {Format::BGRA8_UNORM, VK_FORMAT_B8G8R8A8_UNORM},
    {Format::R16_UNORM, VK_FORMAT_R16_UNORM},
    {Format::R16_SFLOAT, VK_FORMAT_R16_SFLOAT},
    {Format::RG16_SFLOAT, VK_FORMAT_R16G16_SFLOAT},
    {Format::RGBA16_SFLOAT, VK_FORMAT_R16G16B16A16_SFLOAT},
    {Format::R32_SFLOAT, VK_FORMAT_R32_SFLOAT},
    {Format::RG32_SFLOAT, VK_FORMAT_R32G32_SFLOAT},
    {Format::RGBA32_SFLOAT, VK_FORMAT_R32G32B32A32_SFLOAT},
    {Format::R16_UINT, VK_FORMAT_R16_UINT},
    {Format::R32_UINT, VK_FORMAT_R32_UINT},
    {Format::RG32_UINT, VK_FORMAT_R32G32_UINT},
    {Format::RGBA32_UINT, VK_FORMAT_R32G32B32A32_UINT},
    {Format::R10_G10_B10_A2_UNORM, VK_FORMAT_A2B10G10R10_UNORM_PACK32},
    {Format::R11_G11_B10_UFLOAT, VK_FORMAT_B10G11R11_UFLOAT_PACK32},
};
static_assert(sizeof(FORMATS) / sizeof(FORMATS[0]) == (size_t)Format::MAX_NUM, "Format table is out of date");
} // namespace

VkFormat ToVkFormat(Format format)
{
    return (size_t)format < (size_t)Format::MAX_NUM ? FORMATS[(size_t)format].vkFormat : VK_FORMAT_UNDEFINED;
}

Format FromVkFormat(VkFormat vkFormat)
{
    for (const FormatPair& pair : FORMATS)
    {
        if (pair.vkFormat == vkFormat)
            return pair.format;
    }
    return Format::UNKNOWN;
}

VkImageLayout ToVkImageLayout(Layout layout)
{
    switch (layout)
    {
    case Layout::GENERAL:
        return VK_IMAGE_LAYOUT_GENERAL;
    case Layout::SHADER_RESOURCE:
        return VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL;
    case Layout::COPY_SOURCE:
        return VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL;
    case Layout::COPY_DESTINATION:
        return VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL;
    case Layout::COLOR_ATTACHMENT:
        return VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
    case Layout::PRESENT:
        return VK_IMAGE_LAYOUT_PRESENT_SRC_KHR;
    default:
        return VK_IMAGE_LAYOUT_UNDEFINED;
    }
}

bool FromVkImageLayout(VkImageLayout vkLayout, Layout& outLayout)
{
    for (uint32_t i = 0; i < (uint32_t)Layout::MAX_NUM; i++)
    {
        if (ToVkImageLayout((Layout)i) == vkLayout)
        {
            outLayout = (Layout)i;
            return true;
        }
    }
    return false;
}

VkResult ToVkResult(Result result)
{
    switch (result)
    {
    case Result::SUCCESS:
        return VK_SUCCESS;
    case Result::INVALID_ARGUMENT:
        return VK_ERROR_INITIALIZATION_FAILED;
    case Result::UNSUPPORTED:
        return VK_ERROR_FEATURE_NOT_PRESENT;
    case Result::OUT_OF_MEMORY:
        return VK_ERROR_OUT_OF_DEVICE_MEMORY;
    case Result::NOT_READY:
        return VK_NOT_READY;
    case Result::DEVICE_LOST:
        return VK_ERROR_DEVICE_LOST;
    default:
        return VK_ERROR_UNKNOWN;
    }
}

} // namespace rhi
} // namespace nrd
