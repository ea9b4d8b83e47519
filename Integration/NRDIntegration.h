// Vulkan integration layer: executes the denoiser's descriptions (NRD.h) on native Vulkan handles.
//
// It creates the pipelines, samplers, pool textures and buffers, descriptor pools, a ring of
// constant buffers and timestamp queries; per frame it records every barrier and dispatch into
// the application's command buffer. It is written against nrd::rhi (RHI.h): read
// NRDIntegration.cpp to map the descriptions onto another renderer.
//
// Frame flow:
//     integration.SetCommonSettings(common);               // every frame
//     integration.SetMethodSettings(id, sigmaSettings);    // when they change
//     integration.Denoise(commandBuffer, &id, 1, userPool);
//     ... submit; once its fence signalled: integration.GetLastTimings()
//
// Threading: not thread-safe; one thread uses an Integration at a time.
#pragma once

#include "NRD.h"
#include "RHI.h"

#include <vulkan/vulkan.h>

#include <functional>
#include <vector>

namespace nrd
{

struct IntegrationCreationDesc
{
    VkInstance instance = VK_NULL_HANDLE; // (Optional) Enables debug names and labels (VK_EXT_debug_utils).
    VkPhysicalDevice physicalDevice = VK_NULL_HANDLE;
    // Created with shaderStorageImageWriteWithoutFormat enabled (user outputs are storage images
    // without a format qualifier); must outlive the Integration.
    VkDevice device = VK_NULL_HANDLE;
    uint32_t queueFamilyIndex = 0; // Family of the queue the Denoise command buffers go to (compute).
    // Denoise calls whose command buffers may be in flight at once: Denoise call N reuses the
    // descriptors, constants and queries of call N - framesInFlight, which must have completed.
    uint32_t framesInFlight = 2;
    bool enableTimestamps = true;  // Per-dispatch GPU times (GetLastTimings), if the queue supports them.
    const char* name = "NRD";      // (Optional) Prefix of debug names.
};

// An application texture bound as IN_* (sampled image) or OUT_* (storage image, GENERAL layout).
struct UserTexture
{
    VkImage image = VK_NULL_HANDLE;
    // 2D, one mip, color aspect. Inputs: any float-sampleable format (uint for *_UINT inputs) and
    // VK_IMAGE_USAGE_SAMPLED_BIT; outputs: a storage-capable format and VK_IMAGE_USAGE_STORAGE_BIT.
    VkImageView view = VK_NULL_HANDLE;
    VkFormat format = VK_FORMAT_UNDEFINED;
    // In: the layout the image is in when the command buffer reaches Denoise's commands; one of
    // UNDEFINED (contents discarded; outputs only), GENERAL, SHADER_READ_ONLY_OPTIMAL,
    // TRANSFER_SRC/DST_OPTIMAL, COLOR_ATTACHMENT_OPTIMAL, PRESENT_SRC_KHR. Out: the layout it was
    // left in (SHADER_READ_ONLY_OPTIMAL for inputs, GENERAL for outputs), its last access being a
    // compute shader: the application's next barrier waits for VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT.
    VkImageLayout layout = VK_IMAGE_LAYOUT_UNDEFINED;
};

// Application textures indexed by ResourceType. Only the IN_* / OUT_* entries the dispatches of a
// Denoise call reference must be set; the rest are ignored.
struct UserPool
{
    UserTexture textures[(size_t)ResourceType::MAX_NUM] = {};

    UserTexture& operator[](ResourceType type)
    {
        return textures[(size_t)type];
    }
};

struct DispatchTiming
{
    const char* name = nullptr; // DispatchDesc::name (static storage).
    double milliseconds = 0.0;  // GPU time from the end of the previous dispatch (its barriers included).
};

// What one recorded dispatch bound, copied from its DispatchDesc (for byte counts, debugging).
struct RecordedDispatch
{
    const char* name = nullptr;          // DispatchDesc::name (static storage).
    std::vector<ResourceDesc> resources; // In binding order.
    uint16_t gridWidth = 0, gridHeight = 0;
    bool isIndirect = false;
};

// Device memory of the Integration's own resources, from their VkMemoryRequirements.
struct MemoryReport
{
    uint64_t permanentPoolBytes = 0;
    uint64_t transientPoolBytes = 0;
    uint64_t bufferPoolBytes = 0;
    uint64_t constantRingBytes = 0; // Host-visible uniform buffers, all frames in flight.
    uint64_t totalBytes = 0;
};

class Integration
{
public:
    Integration() = default;
    ~Integration()
    {
        Destroy();
    }
    Integration(const Integration&) = delete;
    Integration& operator=(const Integration&) = delete;

    // Creates the core denoiser and every Vulkan object it needs. Pool textures are cleared to zero
    // by the first Denoise. Fails with VK_ERROR_INITIALIZATION_FAILED if the core rejects 'desc'
    // (the reason goes to desc.logCallback) or a Vulkan error code. On failure nothing is left.
    VkResult Create(const IntegrationCreationDesc& integrationDesc, const DenoiserCreationDesc& desc);

    // Forwards to nrd::SetCommonSettings. Call once per frame before Denoise (and after Resize).
    Result SetCommonSettings(const CommonSettings& settings);

    // Forwards to the nrd::SetMethodSettings overload for 'T' (SigmaSettings, ReferenceSettings...).
    // Accepted settings are kept and applied again after Resize.
    template <typename T> Result SetMethodSettings(Identifier identifier, const T& settings)
    {
        if (!m_Denoiser)
            return Result::INVALID_ARGUMENT;
        Result result = nrd::SetMethodSettings(*m_Denoiser, identifier, settings);
        if (result == Result::SUCCESS)
            RememberMethodSettings(identifier, [settings](Denoiser& d, Identifier id) { return nrd::SetMethodSettings(d, id, settings); });
        return result;
    }

    // Records the dispatches of the methods 'identifiers' (all methods if 'identifiersNum' is 0)
    // into 'commandBuffer' (recording, outside a render pass), with every barrier they need.
    // Pool textures and buffers are synchronized against earlier Denoise calls, assuming command
    // buffers execute in the order they were recorded. On return 'userPool' holds the final
    // layouts. Returns VK_ERROR_INITIALIZATION_FAILED (and records nothing) if the core fails or a
    // referenced user texture is missing or in an unsupported layout; the core has then still
    // consumed this frame's settings (call SetCommonSettings again).
    // 'stage' (Optional): with a method that traces between its stages (REFLECTION), call it with
    // DispatchStage::CLASSIFICATION, record the ray pass (GetPoolBuffer gives the ray list and its
    // counters), then call it again with DENOISING for the same SetCommonSettings.
    VkResult Denoise(VkCommandBuffer commandBuffer, const Identifier* identifiers, uint32_t identifiersNum,
                     UserPool& userPool, DispatchStage stage = DispatchStage::ALL);

    // Re-creates the core denoiser and the pool textures / buffers for a new render size; keeps
    // pipelines, layouts and samplers. History restarts (pools cleared again). No Denoise command
    // buffer may be in flight. Call SetCommonSettings again before the next Denoise. On failure the
    // Integration is destroyed (Create it again).
    VkResult Resize(uint16_t renderWidth, uint16_t renderHeight);

    // Per-dispatch GPU times of the last Denoise call, once its command buffer completed; empty if
    // timestamps are disabled or unsupported, or the results are not available yet.
    // '*outTotalMilliseconds' (optional) receives the time from the first dispatch's start to the
    // last one's end.
    std::vector<DispatchTiming> GetLastTimings(double* outTotalMilliseconds = nullptr);

    // As GetLastTimings for an earlier Denoise call: 'callsBack' 0 is the last one, 1 the one before,
    // up to framesInFlight - 1 (several calls recorded back to back, then read once all completed).
    // Empty if 'callsBack' is out of range or that call's results are not available.
    std::vector<DispatchTiming> GetTimings(uint32_t callsBack, double* outTotalMilliseconds = nullptr);

    // The dispatches of the last Denoise call with their resources, in recording order (the order
    // of GetLastTimings).
    std::vector<RecordedDispatch> GetLastDispatches() const;

    MemoryReport GetMemoryReport() const;

    // (Tests, debugging) A pool texture as the last recorded Denoise left it, for reading back.
    struct PoolImage
    {
        VkImage image = VK_NULL_HANDLE; // Null if 'type' / 'index' name no pool texture.
        VkFormat format = VK_FORMAT_UNDEFINED;
        VkImageLayout layout = VK_IMAGE_LAYOUT_UNDEFINED; // UNDEFINED: never written yet.
        uint32_t width = 0;
        uint32_t height = 0;
        rhi::Texture* texture = nullptr; // The same image through nrd::rhi.
        rhi::TextureState state = {};    // 'layout' and the last access, in recording order.
    };
    // 'type' is PERMANENT_POOL or TRANSIENT_POOL, 'index' indexes that DenoiserDesc pool. Read-only:
    // whoever copies from it records a barrier back to 'state' before the next Denoise.
    PoolImage GetPoolImage(ResourceType type, uint32_t index) const;

    // Pool buffer 'index' (DenoiserDesc::buffers) for the application's ray pass, or null. Its last
    // access in recording order is a compute shader write or an indirect-argument read of the
    // Denoise calls recorded so far: the application records a barrier from
    // COMPUTE_SHADER (SHADER_WRITE) before reading it, and one back to COMPUTE_SHADER before the
    // next Denoise call if it writes it (it should not).
    rhi::Buffer* GetPoolBuffer(uint32_t index) const
    {
        return index < m_BufferPool.size() ? m_BufferPool[index].buffer : nullptr;
    }

    // The core description (valid until Resize / Destroy) and the rhi device (for samples).
    const DenoiserDesc& GetDenoiserDesc() const
    {
        return nrd::GetDenoiserDesc(*m_Denoiser);
    }
    rhi::Device& GetDevice()
    {
        return *m_Device;
    }

    // Destroys everything; no Denoise command buffer may be in flight. Safe to call twice.
    void Destroy();

private:
    struct TrackedTexture
    {
        rhi::Texture* texture = nullptr;
        rhi::TextureState state = {}; // What last touched it, in recording order.
    };

    struct TrackedBuffer
    {
        rhi::Buffer* buffer = nullptr;
        uint32_t access = rhi::ACCESS_NONE;
    };

    // Per Denoise call, reused every 'framesInFlight' calls; grows to the largest call seen.
    struct FrameSlot
    {
        rhi::DescriptorPool* descriptorPool = nullptr;
        rhi::DescriptorPoolDesc descriptorCapacity = {};
        rhi::Buffer* constants = nullptr; // Host-visible uniform ring segment.
        uint8_t* constantsData = nullptr;
        uint64_t constantsCapacity = 0;
        rhi::QueryPool* queries = nullptr; // Timestamp before the first dispatch + one after each.
        uint32_t queriesCapacity = 0;
        std::vector<const char*> dispatchNames; // Of the last call recorded in this slot.
        std::vector<RecordedDispatch> dispatches; // Same, with their resources.
    };

    VkResult CreatePipelines();
    VkResult CreatePools();
    void DestroyPools();
    VkResult PrepareSlot(FrameSlot& slot, const DispatchDesc* dispatches, uint32_t dispatchesNum);
    void ClearPools(rhi::CommandBuffer& cmd);
    void RecordBarriers(rhi::CommandBuffer& cmd, const DispatchDesc& dispatch);
    VkResult RecordDispatch(rhi::CommandBuffer& cmd, FrameSlot& slot, const DispatchDesc& dispatch,
                            uint64_t& constantsOffset);
    TrackedTexture& GetTexture(const ResourceDesc& resource);
    void RememberMethodSettings(Identifier identifier, std::function<Result(Denoiser&, Identifier)> apply);
    void Log(const char* message) const;

    IntegrationCreationDesc m_Desc = {};
    DenoiserCreationDesc m_DenoiserCreationDesc = {}; // 'methods' points at m_Methods.
    std::vector<MethodDesc> m_Methods;
    std::vector<std::pair<Identifier, std::function<Result(Denoiser&, Identifier)>>> m_MethodSettings;

    rhi::Device* m_Device = nullptr;
    Denoiser* m_Denoiser = nullptr;
    std::vector<rhi::Sampler*> m_Samplers;       // DenoiserDesc::samplers order.
    std::vector<rhi::Pipeline*> m_Pipelines;     // DenoiserDesc::pipelines order.
    std::vector<TrackedTexture> m_PermanentPool; // DenoiserDesc::permanentPool order.
    std::vector<TrackedTexture> m_TransientPool;
    std::vector<TrackedBuffer> m_BufferPool;
    TrackedTexture m_UserTextures[(size_t)ResourceType::MAX_NUM] = {}; // Wrapped during Denoise only.
    std::vector<FrameSlot> m_Slots;
    uint32_t m_SlotIndex = 0;       // Slot of the next Denoise.
    int32_t m_LastSlot = -1;        // Slot of the last Denoise.
    uint32_t m_DenoiseCalls = 0;    // Recorded Denoise calls since creation.
    bool m_PoolsNeedClear = false;  // Set on (re)creation; the next Denoise clears the pools.
};

} // namespace nrd
