// The executor: maps the core's descriptions (DenoiserDesc once, DispatchDesc per frame) onto
// nrd::rhi. Read top to bottom, it is the recipe for any renderer:
//   1. Create: one sampler per DenoiserDesc::samplers entry; per pipeline a layout with
//      set 0 = its resources in binding order and set 1 = uniform block + immutable samplers;
//      pool textures (storage + sampled, exact formats) and buffers; per frame in flight a
//      descriptor pool, a constant ring segment and timestamp queries.
//   2. Denoise: for each dispatch, transition its resources (barriers), write a fresh descriptor
//      set 0 and set 1, copy its constants into the ring, bind and dispatch.
#include "NRDIntegration.h"

#include "RHIVulkan.h"

#include <algorithm>
#include <cstring>
#include <string>

namespace nrd
{
namespace
{

constexpr uint32_t DivideUp(uint32_t x, uint32_t y)
{
    return (x + y - 1) / y;
}

constexpr uint64_t AlignUp(uint64_t x, uint64_t alignment)
{
    return (x + alignment - 1) / alignment * alignment;
}

VkResult ToVk(rhi::Result result)
{
    return rhi::ToVkResult(result);
}

rhi::Format ToRhi(Format format)
{
    static const rhi::Format table[] = {
        rhi::Format::R8_UNORM,      rhi::Format::RG8_UNORM,     rhi::Format::RGBA8_UNORM,
        rhi::Format::R16_SFLOAT,    rhi::Format::RG16_SFLOAT,   rhi::Format::RGBA16_SFLOAT,
        rhi::Format::R32_SFLOAT,    rhi::Format::RG32_SFLOAT,   rhi::Format::RGBA32_SFLOAT,
        rhi::Format::R32_UINT,      rhi::Format::RG32_UINT,     rhi::Format::R10_G10_B10_A2_UNORM,
        rhi::Format::R11_G11_B10_UFLOAT,
    };
    static_assert(sizeof(table) / sizeof(table[0]) == (size_t)Format::MAX_NUM, "nrd::Format table is out of date");
    return (size_t)format < (size_t)Format::MAX_NUM ? table[(size_t)format] : rhi::Format::UNKNOWN;
}

rhi::DescriptorType ToRhi(DescriptorType type)
{
    switch (type)
    {
    case DescriptorType::TEXTURE:
        return rhi::DescriptorType::SAMPLED_TEXTURE;
    case DescriptorType::STORAGE_TEXTURE:
        return rhi::DescriptorType::STORAGE_TEXTURE;
    case DescriptorType::BUFFER:
        return rhi::DescriptorType::BUFFER;
    default:
        return rhi::DescriptorType::STORAGE_BUFFER;
    }
}

// The state a dispatch needs a resource in.
uint32_t AccessOf(DescriptorType type)
{
    bool isReadOnly = type == DescriptorType::TEXTURE || type == DescriptorType::BUFFER;
    return isReadOnly ? rhi::ACCESS_SHADER_READ : rhi::ACCESS_SHADER_READ_WRITE;
}

bool IsWrite(uint32_t access)
{
    return access & (rhi::ACCESS_SHADER_READ_WRITE | rhi::ACCESS_COPY_DESTINATION | rhi::ACCESS_HOST_WRITE |
                     rhi::ACCESS_UNKNOWN);
}

bool IsUserTexture(ResourceType type)
{
    return type < ResourceType::TRANSIENT_POOL;
}

// Whether going from 'before' to 'after' needs a barrier, and the state afterwards:
//   - RAW: 'before' wrote, 'after' reads -> wait for the write and make it visible.
//   - WAW: both write -> order the writes.
//   - WAR: 'before' read, 'after' writes -> the write waits for the reads (execution only).
//   - layout change (sampled <-> storage, first use) -> a transition, itself a write.
//   - a new kind of reader (e.g. indirect arguments after shader reads) -> make the last write
//     visible to it too; otherwise read-after-read needs nothing and the readers accumulate.
bool NeedsBarrier(uint32_t& access, rhi::Layout& layout, uint32_t afterAccess, rhi::Layout afterLayout)
{
    bool isReadAfterRead = !IsWrite(access) && !IsWrite(afterAccess) && layout == afterLayout;
    if (isReadAfterRead && (afterAccess & ~access) == 0)
        return false;
    access = isReadAfterRead ? (access | afterAccess) : afterAccess;
    layout = afterLayout;
    return true;
}

} // namespace

VkResult Integration::Create(const IntegrationCreationDesc& integrationDesc, const DenoiserCreationDesc& desc)
{
    Destroy();
    m_Desc = integrationDesc;
    m_Desc.framesInFlight = m_Desc.framesInFlight ? m_Desc.framesInFlight : 1;
    m_Methods.assign(desc.methods, desc.methods + (desc.methods ? desc.methodsNum : 0));
    m_DenoiserCreationDesc = desc;
    m_DenoiserCreationDesc.methods = m_Methods.data();

    rhi::DeviceVulkanDesc deviceDesc = {};
    deviceDesc.instance = integrationDesc.instance;
    deviceDesc.physicalDevice = integrationDesc.physicalDevice;
    deviceDesc.device = integrationDesc.device;
    deviceDesc.queueFamilyIndex = integrationDesc.queueFamilyIndex;
    deviceDesc.storageImageWriteWithoutFormatEnabled = true; // Required, see IntegrationCreationDesc::device.
    VkResult result = ToVk(rhi::CreateDeviceVulkan(deviceDesc, m_Device));

    if (result == VK_SUCCESS && CreateDenoiser(m_DenoiserCreationDesc, m_Denoiser) != Result::SUCCESS)
        result = VK_ERROR_INITIALIZATION_FAILED;
    if (result == VK_SUCCESS)
        result = CreatePipelines();
    if (result == VK_SUCCESS)
        result = CreatePools();
    if (result == VK_SUCCESS)
        m_Slots.resize(m_Desc.framesInFlight);

    if (result != VK_SUCCESS)
        Destroy();
    return result;
}

VkResult Integration::CreatePipelines()
{
    const DenoiserDesc& denoiserDesc = nrd::GetDenoiserDesc(*m_Denoiser);
    const SpirvBindingDesc& binding = GetLibraryDesc().spirvBinding;
    if (binding.resourcesSetIndex > 1 || binding.constantsSetIndex > 1 || binding.resourcesSetIndex == binding.constantsSetIndex)
    {
        Log("Integration: the library's binding model (sets other than 0 and 1) is not supported");
        return VK_ERROR_INITIALIZATION_FAILED;
    }

    // Static samplers: clamp-to-edge, nearest or linear.
    for (uint32_t i = 0; i < denoiserDesc.samplersNum; i++)
    {
        rhi::SamplerDesc samplerDesc = {};
        samplerDesc.filter = denoiserDesc.samplers[i] == Sampler::LINEAR_CLAMP ? rhi::Filter::LINEAR : rhi::Filter::NEAREST;
        samplerDesc.addressMode = rhi::AddressMode::CLAMP_TO_EDGE;
        rhi::Sampler* sampler = nullptr;
        rhi::Result result = m_Device->CreateSampler(samplerDesc, sampler);
        if (result != rhi::Result::SUCCESS)
            return ToVk(result);
        m_Samplers.push_back(sampler);
    }

    for (uint32_t p = 0; p < denoiserDesc.pipelinesNum; p++)
    {
        const PipelineDesc& pipelineDesc = denoiserDesc.pipelines[p];

        // Resources set: binding i = i-th resource of the dispatch, types from the ranges.
        std::vector<rhi::DescriptorBindingDesc> resources;
        for (uint32_t r = 0; r < pipelineDesc.resourceRangesNum; r++)
        {
            const ResourceRangeDesc& range = pipelineDesc.resourceRanges[r];
            for (uint32_t i = 0; i < range.descriptorsNum; i++)
                resources.push_back({range.baseBinding + i, ToRhi(range.descriptorType), 1, nullptr});
        }

        // Constants set: the uniform block (if any) and every static sampler, immutable.
        std::vector<rhi::DescriptorBindingDesc> constants;
        if (pipelineDesc.hasConstantData)
            constants.push_back({binding.constantBufferBinding, rhi::DescriptorType::UNIFORM_BUFFER, 1, nullptr});
        for (uint32_t s = 0; s < (uint32_t)m_Samplers.size(); s++)
            constants.push_back({binding.samplersBaseBinding + s, rhi::DescriptorType::SAMPLER, 1, &m_Samplers[s]});

        rhi::DescriptorSetDesc sets[2] = {};
        sets[binding.resourcesSetIndex] = {resources.data(), (uint32_t)resources.size()};
        sets[binding.constantsSetIndex] = {constants.data(), (uint32_t)constants.size()};

        rhi::ComputePipelineDesc computeDesc = {};
        computeDesc.spirv = pipelineDesc.spirv.bytecode;
        computeDesc.spirvSize = pipelineDesc.spirv.size;
        computeDesc.entryPoint = pipelineDesc.entryPointName;
        computeDesc.sets = sets;
        computeDesc.setsNum = 2;
        computeDesc.name = pipelineDesc.shaderIdentifier;
        rhi::Pipeline* pipeline = nullptr;
        rhi::Result result = m_Device->CreateComputePipeline(computeDesc, pipeline);
        if (result != rhi::Result::SUCCESS)
        {
            Log((std::string("Integration: cannot create pipeline ") +
                 (pipelineDesc.shaderIdentifier ? pipelineDesc.shaderIdentifier : "?") + ": " +
                 rhi::GetResultString(result)).c_str());
            return ToVk(result);
        }
        m_Pipelines.push_back(pipeline);
    }
    return VK_SUCCESS;
}

VkResult Integration::CreatePools()
{
    const DenoiserDesc& denoiserDesc = nrd::GetDenoiserDesc(*m_Denoiser);
    std::string prefix = m_Desc.name ? m_Desc.name : "NRD";

    auto createTextures = [&](const TextureDesc* descs, uint32_t num, const char* kind,
                              std::vector<TrackedTexture>& out) -> VkResult {
        for (uint32_t i = 0; i < num; i++)
        {
            std::string name = prefix + " " + kind + " " + std::to_string(i);
            rhi::TextureDesc textureDesc = {};
            textureDesc.format = ToRhi(descs[i].format);
            textureDesc.width = DivideUp(denoiserDesc.renderWidth, descs[i].downsampleX);
            textureDesc.height = DivideUp(denoiserDesc.renderHeight, descs[i].downsampleY);
            textureDesc.usage = rhi::TEXTURE_USAGE_SAMPLED | rhi::TEXTURE_USAGE_STORAGE |
                                rhi::TEXTURE_USAGE_COPY_SOURCE | rhi::TEXTURE_USAGE_COPY_DESTINATION;
            textureDesc.name = name.c_str();
            TrackedTexture texture = {};
            rhi::Result result = m_Device->CreateTexture(textureDesc, texture.texture);
            if (result != rhi::Result::SUCCESS)
            {
                Log((std::string("Integration: cannot create ") + name + " (" + GetFormatString(descs[i].format) +
                     "): " + rhi::GetResultString(result)).c_str());
                return ToVk(result);
            }
            out.push_back(texture);
        }
        return VK_SUCCESS;
    };

    VkResult result = createTextures(denoiserDesc.permanentPool, denoiserDesc.permanentPoolSize, "permanent", m_PermanentPool);
    if (result == VK_SUCCESS)
        result = createTextures(denoiserDesc.transientPool, denoiserDesc.transientPoolSize, "transient", m_TransientPool);

    for (uint32_t i = 0; i < denoiserDesc.buffersNum && result == VK_SUCCESS; i++)
    {
        std::string name = prefix + " buffer " + std::to_string(i);
        rhi::BufferDesc bufferDesc = {};
        bufferDesc.size = denoiserDesc.buffers[i].size;
        bufferDesc.usage = rhi::BUFFER_USAGE_STORAGE | rhi::BUFFER_USAGE_COPY_SOURCE | rhi::BUFFER_USAGE_COPY_DESTINATION;
        if (denoiserDesc.buffers[i].isIndirectArguments)
            bufferDesc.usage |= rhi::BUFFER_USAGE_INDIRECT_ARGUMENTS;
        bufferDesc.name = name.c_str();
        TrackedBuffer buffer = {};
        result = ToVk(m_Device->CreateBuffer(bufferDesc, buffer.buffer));
        if (result == VK_SUCCESS)
            m_BufferPool.push_back(buffer);
    }

    m_PoolsNeedClear = true;
    return result;
}

void Integration::DestroyPools()
{
    for (TrackedTexture& texture : m_PermanentPool)
        m_Device->DestroyTexture(texture.texture);
    for (TrackedTexture& texture : m_TransientPool)
        m_Device->DestroyTexture(texture.texture);
    for (TrackedBuffer& buffer : m_BufferPool)
        m_Device->DestroyBuffer(buffer.buffer);
    m_PermanentPool.clear();
    m_TransientPool.clear();
    m_BufferPool.clear();
}

void Integration::Destroy()
{
    if (m_Device)
    {
        DestroyPools();
        for (FrameSlot& slot : m_Slots)
        {
            m_Device->DestroyDescriptorPool(slot.descriptorPool);
            m_Device->DestroyBuffer(slot.constants);
            m_Device->DestroyQueryPool(slot.queries);
        }
        for (rhi::Pipeline* pipeline : m_Pipelines)
            m_Device->DestroyPipeline(pipeline);
        for (rhi::Sampler* sampler : m_Samplers)
            m_Device->DestroySampler(sampler);
        rhi::DestroyDevice(m_Device);
    }
    DestroyDenoiser(m_Denoiser);

    m_Device = nullptr;
    m_Denoiser = nullptr;
    m_Slots.clear();
    m_Pipelines.clear();
    m_Samplers.clear();
    m_MethodSettings.clear();
    m_SlotIndex = 0;
    m_LastSlot = -1;
    m_DenoiseCalls = 0;
}

Result Integration::SetCommonSettings(const CommonSettings& settings)
{
    if (!m_Denoiser)
        return Result::INVALID_ARGUMENT;
    return nrd::SetCommonSettings(*m_Denoiser, settings);
}

void Integration::RememberMethodSettings(Identifier identifier, std::function<Result(Denoiser&, Identifier)> apply)
{
    for (auto& entry : m_MethodSettings)
    {
        if (entry.first == identifier)
        {
            entry.second = std::move(apply);
            return;
        }
    }
    m_MethodSettings.emplace_back(identifier, std::move(apply));
}

VkResult Integration::Resize(uint16_t renderWidth, uint16_t renderHeight)
{
    if (!m_Device)
        return VK_ERROR_INITIALIZATION_FAILED;

    DestroyPools();
    DestroyDenoiser(m_Denoiser);
    m_Denoiser = nullptr;

    m_DenoiserCreationDesc.renderWidth = renderWidth;
    m_DenoiserCreationDesc.renderHeight = renderHeight;
    if (CreateDenoiser(m_DenoiserCreationDesc, m_Denoiser) != Result::SUCCESS)
    {
        Destroy();
        return VK_ERROR_INITIALIZATION_FAILED;
    }
    // Same methods, hence the same pipelines: only the pools depend on the size.
    for (auto& entry : m_MethodSettings)
        entry.second(*m_Denoiser, entry.first);

    VkResult result = CreatePools();
    if (result != VK_SUCCESS)
        Destroy();
    return result;
}

Integration::TrackedTexture& Integration::GetTexture(const ResourceDesc& resource)
{
    if (resource.type == ResourceType::PERMANENT_POOL)
        return m_PermanentPool[resource.indexInPool];
    if (resource.type == ResourceType::TRANSIENT_POOL)
        return m_TransientPool[resource.indexInPool];
    return m_UserTextures[(size_t)resource.type];
}

// Makes sure the slot's descriptor pool, constant ring segment and queries fit this call.
VkResult Integration::PrepareSlot(FrameSlot& slot, const DispatchDesc* dispatches, uint32_t dispatchesNum)
{
    const DenoiserDesc& denoiserDesc = nrd::GetDenoiserDesc(*m_Denoiser);
    const rhi::DeviceDesc& deviceDesc = m_Device->GetDesc();

    // Start from the core's per-frame estimate (one resources set and one constants set per
    // dispatch), then make sure this call's actual dispatches fit.
    const DescriptorPoolDesc& estimate = denoiserDesc.descriptorPoolDesc;
    rhi::DescriptorPoolDesc fromCore = {};
    fromCore.setsMaxNum = estimate.setsMaxNum * 2;
    fromCore.descriptorsMaxNum[(size_t)rhi::DescriptorType::SAMPLED_TEXTURE] = estimate.texturesMaxNum;
    fromCore.descriptorsMaxNum[(size_t)rhi::DescriptorType::STORAGE_TEXTURE] = estimate.storageTexturesMaxNum;
    fromCore.descriptorsMaxNum[(size_t)rhi::DescriptorType::STORAGE_BUFFER] = estimate.buffersMaxNum;
    fromCore.descriptorsMaxNum[(size_t)rhi::DescriptorType::UNIFORM_BUFFER] = estimate.constantBuffersMaxNum;
    fromCore.descriptorsMaxNum[(size_t)rhi::DescriptorType::SAMPLER] = estimate.samplersMaxNum;

    rhi::DescriptorPoolDesc needed = {};
    uint64_t constantsSize = 0;
    for (uint32_t d = 0; d < dispatchesNum; d++)
    {
        const DispatchDesc& dispatch = dispatches[d];
        const PipelineDesc& pipelineDesc = denoiserDesc.pipelines[dispatch.pipelineIndex];
        needed.setsMaxNum += 2;
        for (uint32_t r = 0; r < dispatch.resourcesNum; r++)
            needed.descriptorsMaxNum[(size_t)ToRhi(dispatch.resources[r].descriptorType)]++;
        needed.descriptorsMaxNum[(size_t)rhi::DescriptorType::SAMPLER] += denoiserDesc.samplersNum;
        if (pipelineDesc.hasConstantData)
        {
            needed.descriptorsMaxNum[(size_t)rhi::DescriptorType::UNIFORM_BUFFER]++;
            uint32_t blockSize = std::max(pipelineDesc.constantBufferSize, dispatch.constantBufferDataSize);
            constantsSize += AlignUp(blockSize, deviceDesc.uniformBufferOffsetAlignment);
        }
    }

    bool fits = slot.descriptorPool && needed.setsMaxNum <= slot.descriptorCapacity.setsMaxNum;
    for (uint32_t t = 0; t < (uint32_t)rhi::DescriptorType::MAX_NUM; t++)
        fits = fits && needed.descriptorsMaxNum[t] <= slot.descriptorCapacity.descriptorsMaxNum[t];
    if (!fits)
    {
        m_Device->DestroyDescriptorPool(slot.descriptorPool);
        slot.descriptorPool = nullptr;
        for (uint32_t t = 0; t < (uint32_t)rhi::DescriptorType::MAX_NUM; t++)
        {
            needed.descriptorsMaxNum[t] = std::max({needed.descriptorsMaxNum[t], fromCore.descriptorsMaxNum[t],
                                                    slot.descriptorCapacity.descriptorsMaxNum[t]});
        }
        needed.setsMaxNum = std::max({needed.setsMaxNum, fromCore.setsMaxNum, slot.descriptorCapacity.setsMaxNum, 2u});
        slot.descriptorCapacity = needed;
        rhi::Result result = m_Device->CreateDescriptorPool(needed, slot.descriptorPool);
        if (result != rhi::Result::SUCCESS)
            return ToVk(result);
    }
    else
    {
        rhi::Result result = m_Device->ResetDescriptorPool(*slot.descriptorPool);
        if (result != rhi::Result::SUCCESS)
            return ToVk(result);
    }

    if (constantsSize > slot.constantsCapacity)
    {
        // Forget the old ring first: if the new one cannot be created, a later call that fits the
        // old size must create it again rather than write through the freed mapping.
        m_Device->DestroyBuffer(slot.constants);
        slot.constants = nullptr;
        slot.constantsData = nullptr;
        slot.constantsCapacity = 0;
        rhi::BufferDesc bufferDesc = {};
        bufferDesc.size = constantsSize;
        bufferDesc.usage = rhi::BUFFER_USAGE_UNIFORM;
        bufferDesc.location = rhi::MemoryLocation::HOST_UPLOAD;
        bufferDesc.name = "NRD constants";
        rhi::Result result = m_Device->CreateBuffer(bufferDesc, slot.constants);
        if (result != rhi::Result::SUCCESS)
            return ToVk(result);
        slot.constantsData = (uint8_t*)m_Device->MapBuffer(*slot.constants);
        slot.constantsCapacity = constantsSize;
    }

    uint32_t queriesNum = dispatchesNum + 1;
    if (m_Desc.enableTimestamps && deviceDesc.timestampsSupported && queriesNum > slot.queriesCapacity)
    {
        m_Device->DestroyQueryPool(slot.queries);
        slot.queries = nullptr;
        slot.queriesCapacity = 0;
        rhi::Result result = m_Device->CreateQueryPool(queriesNum, slot.queries);
        if (result != rhi::Result::SUCCESS)
            return ToVk(result);
        slot.queriesCapacity = queriesNum;
    }
    return VK_SUCCESS;
}

// First Denoise after (re)creation: history starts at zero, never garbage (NaN).
void Integration::ClearPools(rhi::CommandBuffer& cmd)
{
    // Transient textures too: their first frame then starts from zeros, not from stale memory.
    std::vector<TrackedTexture*> textures;
    for (TrackedTexture& texture : m_PermanentPool)
        textures.push_back(&texture);
    for (TrackedTexture& texture : m_TransientPool)
        textures.push_back(&texture);
    std::vector<rhi::TextureBarrier> barriers;
    for (TrackedTexture* texture : textures)
    {
        // Layout transition from UNDEFINED (first use, nothing to wait for).
        rhi::TextureState cleared = {rhi::ACCESS_COPY_DESTINATION, rhi::Layout::COPY_DESTINATION};
        barriers.push_back({texture->texture, texture->state, cleared});
        texture->state = cleared;
    }
    rhi::BarrierDesc barrierDesc = {};
    barrierDesc.textures = barriers.data();
    barrierDesc.texturesNum = (uint32_t)barriers.size();
    m_Device->CmdBarrier(cmd, barrierDesc);

    const float zero[4] = {};
    for (TrackedTexture* texture : textures)
        m_Device->CmdClearTexture(cmd, *texture->texture, rhi::Layout::COPY_DESTINATION, zero);
    for (TrackedBuffer& buffer : m_BufferPool)
    {
        m_Device->CmdFillBuffer(cmd, *buffer.buffer, 0, 0, 0);
        buffer.access = rhi::ACCESS_COPY_DESTINATION;
    }
    m_PoolsNeedClear = false;
}

// Puts every resource of 'dispatch' in the state it needs, in one barrier batch.
void Integration::RecordBarriers(rhi::CommandBuffer& cmd, const DispatchDesc& dispatch)
{
    std::vector<rhi::TextureBarrier> textureBarriers;
    std::vector<rhi::BufferBarrier> bufferBarriers;

    // What each pool buffer is used for in this dispatch (a buffer may be both bound and the
    // indirect argument source).
    std::vector<uint32_t> bufferUse(m_BufferPool.size(), rhi::ACCESS_NONE);
    if (dispatch.isIndirect)
        bufferUse[dispatch.indirectArgumentsBuffer] |= rhi::ACCESS_INDIRECT_ARGUMENTS;

    for (uint32_t r = 0; r < dispatch.resourcesNum; r++)
    {
        const ResourceDesc& resource = dispatch.resources[r];
        uint32_t access = AccessOf(resource.descriptorType);
        if (resource.type == ResourceType::BUFFER_POOL)
        {
            bufferUse[resource.indexInPool] |= access;
            continue;
        }

        // Sampled textures in SHADER_READ_ONLY_OPTIMAL, storage textures in GENERAL.
        rhi::Layout layout = resource.descriptorType == DescriptorType::TEXTURE ? rhi::Layout::SHADER_RESOURCE
                                                                                : rhi::Layout::GENERAL;
        TrackedTexture& texture = GetTexture(resource);
        rhi::TextureState before = texture.state;
        // RAW / WAR / WAW against the previous user of the texture, or a layout transition.
        if (NeedsBarrier(texture.state.access, texture.state.layout, access, layout))
            textureBarriers.push_back({texture.texture, before, texture.state});
    }

    for (size_t b = 0; b < m_BufferPool.size(); b++)
    {
        TrackedBuffer& buffer = m_BufferPool[b];
        rhi::Layout ignored = rhi::Layout::GENERAL;
        uint32_t before = buffer.access;
        // RAW / WAR / WAW against the previous user of the buffer, or a new reader (indirect).
        if (bufferUse[b] && NeedsBarrier(buffer.access, ignored, bufferUse[b], rhi::Layout::GENERAL))
            bufferBarriers.push_back({buffer.buffer, before, buffer.access});
    }

    if (textureBarriers.empty() && bufferBarriers.empty())
        return;
    rhi::BarrierDesc barrierDesc = {};
    barrierDesc.textures = textureBarriers.data();
    barrierDesc.texturesNum = (uint32_t)textureBarriers.size();
    barrierDesc.buffers = bufferBarriers.data();
    barrierDesc.buffersNum = (uint32_t)bufferBarriers.size();
    m_Device->CmdBarrier(cmd, barrierDesc);
}

VkResult Integration::RecordDispatch(rhi::CommandBuffer& cmd, FrameSlot& slot, const DispatchDesc& dispatch,
                                     uint64_t& constantsOffset)
{
    const DenoiserDesc& denoiserDesc = nrd::GetDenoiserDesc(*m_Denoiser);
    const SpirvBindingDesc& binding = GetLibraryDesc().spirvBinding;
    const PipelineDesc& pipelineDesc = denoiserDesc.pipelines[dispatch.pipelineIndex];
    rhi::Pipeline& pipeline = *m_Pipelines[dispatch.pipelineIndex];

    // Set 0: the dispatch's resources, binding i = resource i.
    rhi::DescriptorSet* resources = nullptr;
    rhi::Result result = m_Device->AllocateDescriptorSet(*slot.descriptorPool, pipeline, binding.resourcesSetIndex, resources);
    if (result != rhi::Result::SUCCESS)
        return ToVk(result);
    std::vector<rhi::DescriptorWrite> writes(dispatch.resourcesNum);
    for (uint32_t r = 0; r < dispatch.resourcesNum; r++)
    {
        const ResourceDesc& resource = dispatch.resources[r];
        writes[r].binding = r;
        writes[r].type = ToRhi(resource.descriptorType);
        if (resource.type == ResourceType::BUFFER_POOL)
            writes[r].buffer = m_BufferPool[resource.indexInPool].buffer;
        else
            writes[r].texture = GetTexture(resource).texture;
    }
    m_Device->UpdateDescriptorSet(*resources, writes.data(), (uint32_t)writes.size());

    // Set 1: the constants, copied into this slot's ring segment (samplers are immutable).
    rhi::DescriptorSet* constants = nullptr;
    result = m_Device->AllocateDescriptorSet(*slot.descriptorPool, pipeline, binding.constantsSetIndex, constants);
    if (result != rhi::Result::SUCCESS)
        return ToVk(result);
    if (pipelineDesc.hasConstantData)
    {
        uint32_t blockSize = std::max(pipelineDesc.constantBufferSize, dispatch.constantBufferDataSize);
        std::memset(slot.constantsData + constantsOffset, 0, blockSize);
        std::memcpy(slot.constantsData + constantsOffset, dispatch.constantBufferData, dispatch.constantBufferDataSize);

        rhi::DescriptorWrite write = {};
        write.binding = binding.constantBufferBinding;
        write.type = rhi::DescriptorType::UNIFORM_BUFFER;
        write.buffer = slot.constants;
        write.offset = constantsOffset;
        write.range = blockSize;
        m_Device->UpdateDescriptorSet(*constants, &write, 1);
        constantsOffset += AlignUp(blockSize, m_Device->GetDesc().uniformBufferOffsetAlignment);
    }

    RecordBarriers(cmd, dispatch);

    m_Device->CmdBindPipeline(cmd, pipeline);
    m_Device->CmdBindDescriptorSet(cmd, pipeline, binding.resourcesSetIndex, *resources);
    m_Device->CmdBindDescriptorSet(cmd, pipeline, binding.constantsSetIndex, *constants);
    if (dispatch.isIndirect)
        m_Device->CmdDispatchIndirect(cmd, *m_BufferPool[dispatch.indirectArgumentsBuffer].buffer, dispatch.indirectArgumentsOffset);
    else
        m_Device->CmdDispatch(cmd, dispatch.gridWidth, dispatch.gridHeight, 1);
    return VK_SUCCESS;
}

VkResult Integration::Denoise(VkCommandBuffer commandBuffer, const Identifier* identifiers, uint32_t identifiersNum,
                              UserPool& userPool, DispatchStage stage)
{
    if (!m_Device)
        return VK_ERROR_INITIALIZATION_FAILED;

    const DispatchDesc* dispatches = nullptr;
    uint32_t dispatchesNum = 0;
    if (GetComputeDispatches(*m_Denoiser, identifiers, identifiersNum, stage, dispatches, dispatchesNum) != Result::SUCCESS)
        return VK_ERROR_INITIALIZATION_FAILED;

    // Wrap the user textures the dispatches reference; their state is the layout the application
    // gave and an unknown previous access (anything may have written them).
    VkResult result = VK_SUCCESS;
    for (uint32_t d = 0; d < dispatchesNum && result == VK_SUCCESS; d++)
    {
        for (uint32_t r = 0; r < dispatches[d].resourcesNum && result == VK_SUCCESS; r++)
        {
            ResourceType type = dispatches[d].resources[r].type;
            TrackedTexture& tracked = m_UserTextures[(size_t)type];
            if (!IsUserTexture(type) || tracked.texture)
                continue;
            const UserTexture& user = userPool.textures[(size_t)type];
            rhi::TextureVulkanDesc wrapDesc = {};
            wrapDesc.image = user.image;
            wrapDesc.view = user.view;
            wrapDesc.format = user.format;
            tracked.state.access = rhi::ACCESS_UNKNOWN;
            if (!rhi::FromVkImageLayout(user.layout, tracked.state.layout) ||
                rhi::WrapTextureVulkan(*m_Device, wrapDesc, tracked.texture) != rhi::Result::SUCCESS)
            {
                Log((std::string("Integration: user texture ") + GetResourceTypeString(type) +
                     " is missing or in an unsupported layout").c_str());
                result = VK_ERROR_INITIALIZATION_FAILED;
            }
        }
    }

    FrameSlot& slot = m_Slots[m_SlotIndex];
    if (result == VK_SUCCESS)
        result = PrepareSlot(slot, dispatches, dispatchesNum);

    rhi::CommandBuffer& cmd = rhi::GetCommandBuffer(commandBuffer);
    if (result == VK_SUCCESS)
    {
        m_Device->CmdBeginLabel(cmd, m_Desc.name ? m_Desc.name : "NRD");
        if (m_PoolsNeedClear)
            ClearPools(cmd);

        slot.dispatchNames.clear();
        slot.dispatches.clear();
        if (slot.queries)
        {
            m_Device->CmdResetQueries(cmd, *slot.queries, 0, dispatchesNum + 1);
            m_Device->CmdWriteTimestamp(cmd, *slot.queries, 0);
        }

        uint64_t constantsOffset = 0;
        for (uint32_t d = 0; d < dispatchesNum && result == VK_SUCCESS; d++)
        {
            m_Device->CmdBeginLabel(cmd, dispatches[d].name);
            result = RecordDispatch(cmd, slot, dispatches[d], constantsOffset);
            m_Device->CmdEndLabel(cmd);
            if (slot.queries)
                m_Device->CmdWriteTimestamp(cmd, *slot.queries, d + 1);
            slot.dispatchNames.push_back(dispatches[d].name);
            RecordedDispatch recorded;
            recorded.name = dispatches[d].name;
            recorded.resources.assign(dispatches[d].resources, dispatches[d].resources + dispatches[d].resourcesNum);
            recorded.gridWidth = dispatches[d].gridWidth;
            recorded.gridHeight = dispatches[d].gridHeight;
            recorded.isIndirect = dispatches[d].isIndirect;
            slot.dispatches.push_back(std::move(recorded));
        }
        m_Device->CmdEndLabel(cmd);

        m_LastSlot = (int32_t)m_SlotIndex;
        m_DenoiseCalls++;
        m_SlotIndex = (m_SlotIndex + 1) % (uint32_t)m_Slots.size();
    }

    // Hand the user textures back with their final layouts.
    for (uint32_t t = 0; t < (uint32_t)ResourceType::TRANSIENT_POOL; t++)
    {
        TrackedTexture& tracked = m_UserTextures[t];
        if (!tracked.texture)
            continue;
        if (result == VK_SUCCESS)
            userPool.textures[t].layout = rhi::ToVkImageLayout(tracked.state.layout);
        m_Device->DestroyTexture(tracked.texture);
        tracked = {};
    }
    return result;
}

std::vector<DispatchTiming> Integration::GetLastTimings(double* outTotalMilliseconds)
{
    return GetTimings(0, outTotalMilliseconds);
}

std::vector<DispatchTiming> Integration::GetTimings(uint32_t callsBack, double* outTotalMilliseconds)
{
    std::vector<DispatchTiming> timings;
    if (outTotalMilliseconds)
        *outTotalMilliseconds = 0.0;
    const uint32_t slotsNum = (uint32_t)m_Slots.size();
    if (m_LastSlot < 0 || callsBack >= slotsNum || callsBack >= m_DenoiseCalls)
        return timings;
    FrameSlot& slot = m_Slots[((uint32_t)m_LastSlot + slotsNum - callsBack) % slotsNum];
    if (!slot.queries)
        return timings;

    uint32_t num = (uint32_t)slot.dispatchNames.size();
    std::vector<uint64_t> ticks(num + 1);
    if (m_Device->GetTimestamps(*slot.queries, 0, num + 1, ticks.data()) != rhi::Result::SUCCESS)
        return timings;

    double msPerTick = m_Device->GetDesc().timestampPeriodNs * 1e-6;
    for (uint32_t d = 0; d < num; d++)
        timings.push_back({slot.dispatchNames[d], double(ticks[d + 1] - ticks[d]) * msPerTick});
    if (outTotalMilliseconds)
        *outTotalMilliseconds = double(ticks[num] - ticks[0]) * msPerTick;
    return timings;
}

std::vector<RecordedDispatch> Integration::GetLastDispatches() const
{
    if (m_LastSlot < 0)
        return {};
    return m_Slots[m_LastSlot].dispatches;
}

Integration::PoolImage Integration::GetPoolImage(ResourceType type, uint32_t index) const
{
    PoolImage image = {};
    const std::vector<TrackedTexture>* pool = type == ResourceType::PERMANENT_POOL   ? &m_PermanentPool
                                              : type == ResourceType::TRANSIENT_POOL ? &m_TransientPool
                                                                                     : nullptr;
    if (!m_Device || !pool || index >= pool->size())
        return image;
    const TrackedTexture& tracked = (*pool)[index];
    const rhi::TextureDesc& desc = m_Device->GetTextureDesc(*tracked.texture);
    image.image = rhi::GetVkImage(*tracked.texture);
    image.format = rhi::ToVkFormat(desc.format);
    image.layout = rhi::ToVkImageLayout(tracked.state.layout);
    image.width = desc.width;
    image.height = desc.height;
    image.texture = tracked.texture;
    image.state = tracked.state;
    return image;
}

MemoryReport Integration::GetMemoryReport() const
{
    MemoryReport report = {};
    if (!m_Device)
        return report;
    for (const TrackedTexture& texture : m_PermanentPool)
        report.permanentPoolBytes += m_Device->GetTextureMemorySize(*texture.texture);
    for (const TrackedTexture& texture : m_TransientPool)
        report.transientPoolBytes += m_Device->GetTextureMemorySize(*texture.texture);
    for (const TrackedBuffer& buffer : m_BufferPool)
        report.bufferPoolBytes += m_Device->GetBufferMemorySize(*buffer.buffer);
    for (const FrameSlot& slot : m_Slots)
        report.constantRingBytes += slot.constants ? m_Device->GetBufferMemorySize(*slot.constants) : 0;
    report.totalBytes = report.permanentPoolBytes + report.transientPoolBytes + report.bufferPoolBytes +
                        report.constantRingBytes;
    return report;
}

void Integration::Log(const char* message) const
{
    if (m_DenoiserCreationDesc.logCallback)
        m_DenoiserCreationDesc.logCallback(m_DenoiserCreationDesc.logUserArg, LogSeverity::ERROR, message);
}

} // namespace nrd
