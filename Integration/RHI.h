// A thin rendering interface for compute work: device, textures, buffers, compute pipelines,
// descriptor sets, barriers, dispatches, copies, host-visible buffers and timestamp queries.
//
// Written for the NRD executor (NRDIntegration.cpp) and the samples (scene lab, benchmark), but
// not specific to the denoiser. One backend today, Vulkan (RHIVulkan.h creates the device and
// wraps native handles); another backend implements 'Device' and adds its own creation header.
//
// Conventions:
//   - Objects are opaque and created / destroyed through the Device that made them.
//   - Functions return Result; SUCCESS is the only success code. Nothing throws.
//   - Recording functions are named Cmd*; they take the CommandBuffer being recorded.
//   - Synchronization is explicit: the caller tracks each resource's Access and Layout and records
//     CmdBarrier between uses (see AccessBits). The device tracks nothing.
//   - Textures are 2D, one mip, one layer, color. Copies move the whole texture, rows tightly packed.
#pragma once

#include <cstddef>
#include <cstdint>

namespace nrd
{
namespace rhi
{

struct Texture;       // Image + view.
struct Buffer;        // Linear memory.
struct Sampler;       // Sampler state.
struct Pipeline;      // Compute pipeline + its descriptor set layouts.
struct DescriptorPool;
struct DescriptorSet; // Valid until its pool is reset or destroyed.
struct QueryPool;     // Timestamp queries.
struct CommandBuffer; // A recording command buffer (Vulkan: the VkCommandBuffer itself).

enum class Result : uint32_t
{
    SUCCESS,
    FAILURE,              // Unexpected backend error.
    INVALID_ARGUMENT,     // Bad description (zero size, unknown format, null pointer...).
    UNSUPPORTED,          // The device lacks a feature, format or usage.
    OUT_OF_MEMORY,        // Host or device memory exhausted, or a descriptor pool is full.
    NOT_READY,            // Query results not available yet.
    DEVICE_LOST,

    MAX_NUM
};

enum class Format : uint32_t
{
    UNKNOWN, // Wrapped native textures whose format has no equivalent here; cannot be copied.

    R8_UNORM,
    RG8_UNORM,
    RGBA8_UNORM,
    RGBA8_SRGB,
    BGRA8_UNORM,
    R16_UNORM,
    R16_SFLOAT,
    RG16_SFLOAT,
    RGBA16_SFLOAT,
    R32_SFLOAT,
    RG32_SFLOAT,
    RGBA32_SFLOAT,
    R16_UINT,
    R32_UINT,
    RG32_UINT,
    RGBA32_UINT,
    R10_G10_B10_A2_UNORM,
    R11_G11_B10_UFLOAT,

    MAX_NUM
};

struct FormatInfo
{
    const char* name;
    uint8_t bytesPerPixel; // 0 for UNKNOWN.
    uint8_t channelNum;    // 1..4; 0 for UNKNOWN.
    bool isInteger;        // *_UINT: sampled as utexture2D / uimage2D.
};

// Never fails; out-of-range values give UNKNOWN's entry.
inline const FormatInfo& GetFormatInfo(Format format)
{
    static const FormatInfo table[] = {
        {"UNKNOWN", 0, 0, false},
        {"R8_UNORM", 1, 1, false},
        {"RG8_UNORM", 2, 2, false},
        {"RGBA8_UNORM", 4, 4, false},
        {"RGBA8_SRGB", 4, 4, false},
        {"BGRA8_UNORM", 4, 4, false},
        {"R16_UNORM", 2, 1, false},
        {"R16_SFLOAT", 2, 1, false},
        {"RG16_SFLOAT", 4, 2, false},
        {"RGBA16_SFLOAT", 8, 4, false},
        {"R32_SFLOAT", 4, 1, false},
        {"RG32_SFLOAT", 8, 2, false},
        {"RGBA32_SFLOAT", 16, 4, false},
        {"R16_UINT", 2, 1, true},
        {"R32_UINT", 4, 1, true},
        {"RG32_UINT", 8, 2, true},
        {"RGBA32_UINT", 16, 4, true},
        {"R10_G10_B10_A2_UNORM", 4, 4, false},
        {"R11_G11_B10_UFLOAT", 4, 3, false},
    };
    static_assert(sizeof(table) / sizeof(table[0]) == (size_t)Format::MAX_NUM, "Format table is out of date");
    return (size_t)format < (size_t)Format::MAX_NUM ? table[(size_t)format] : table[0];
}

inline uint32_t GetFormatBytesPerPixel(Format format)
{
    return GetFormatInfo(format).bytesPerPixel;
}

// Readable name, never null.
inline const char* GetResultString(Result result)
{
    static const char* names[] = {"SUCCESS", "FAILURE", "INVALID_ARGUMENT", "UNSUPPORTED", "OUT_OF_MEMORY",
                                  "NOT_READY", "DEVICE_LOST"};
    static_assert(sizeof(names) / sizeof(names[0]) == (size_t)Result::MAX_NUM, "Result names are out of date");
    return (size_t)result < (size_t)Result::MAX_NUM ? names[(size_t)result] : "UNKNOWN";
}

// ------------------------------------------------------------------------------------------------
// Resources

enum TextureUsageBits : uint32_t
{
    TEXTURE_USAGE_SAMPLED = 1 << 0,          // Read through a sampled-image descriptor.
    TEXTURE_USAGE_STORAGE = 1 << 1,          // Read / written through a storage-image descriptor.
    TEXTURE_USAGE_COPY_SOURCE = 1 << 2,      // CmdCopyTextureToBuffer.
    TEXTURE_USAGE_COPY_DESTINATION = 1 << 3, // CmdCopyBufferToTexture, CmdClearTexture.
};

struct TextureDesc
{
    Format format = Format::UNKNOWN;
    uint32_t width = 0;
    uint32_t height = 0;
    uint32_t usage = 0;           // TextureUsageBits.
    const char* name = nullptr;   // (Optional) Debug name, shown by validation layers / debuggers.
};

enum BufferUsageBits : uint32_t
{
    BUFFER_USAGE_STORAGE = 1 << 0,           // Storage-buffer descriptor (read-only or read-write).
    BUFFER_USAGE_UNIFORM = 1 << 1,           // Uniform-buffer descriptor.
    BUFFER_USAGE_INDIRECT_ARGUMENTS = 1 << 2, // CmdDispatchIndirect.
    BUFFER_USAGE_COPY_SOURCE = 1 << 3,
    BUFFER_USAGE_COPY_DESTINATION = 1 << 4,  // Also CmdFillBuffer.
};

enum class MemoryLocation : uint32_t
{
    DEVICE,        // Device-local, not mappable.
    HOST_UPLOAD,   // Host-visible and coherent, written by the host, read by the device.
    HOST_READBACK, // Host-visible and coherent (cached where possible), written by the device.
};

struct BufferDesc
{
    uint64_t size = 0; // Bytes.
    uint32_t usage = 0; // BufferUsageBits.
    MemoryLocation location = MemoryLocation::DEVICE;
    const char* name = nullptr; // (Optional)
};

enum class Filter : uint32_t
{
    NEAREST,
    LINEAR,
};

enum class AddressMode : uint32_t
{
    CLAMP_TO_EDGE,
    REPEAT,
    MIRRORED_REPEAT,
};

struct SamplerDesc
{
    Filter filter = Filter::NEAREST; // Min and mag; mips are not used.
    AddressMode addressMode = AddressMode::CLAMP_TO_EDGE; // U, V and W.
};

// ------------------------------------------------------------------------------------------------
// Pipelines and descriptors

enum class DescriptorType : uint32_t
{
    SAMPLED_TEXTURE, // texture2D / utexture2D (Vulkan: SAMPLED_IMAGE).
    STORAGE_TEXTURE, // image2D / uimage2D (Vulkan: STORAGE_IMAGE), GENERAL layout.
    BUFFER,          // readonly buffer (Vulkan: STORAGE_BUFFER).
    STORAGE_BUFFER,  // buffer (Vulkan: STORAGE_BUFFER).
    UNIFORM_BUFFER,  // uniform block, std140.
    SAMPLER,         // sampler; immutable when 'immutableSamplers' is set.

    MAX_NUM
};

struct DescriptorBindingDesc
{
    uint32_t binding = 0;
    DescriptorType type = DescriptorType::MAX_NUM;
    uint32_t count = 1; // Array size (1 for a plain binding).
    // (Optional, SAMPLER only) 'count' samplers baked into the layout; no DescriptorWrite needed.
    Sampler* const* immutableSamplers = nullptr;
};

// One descriptor set layout. Sets of a pipeline are numbered by their position in
// ComputePipelineDesc::sets (set 0, set 1, ...); an empty set (bindingsNum 0) is allowed.
struct DescriptorSetDesc
{
    const DescriptorBindingDesc* bindings = nullptr;
    uint32_t bindingsNum = 0;
};

struct ComputePipelineDesc
{
    const void* spirv = nullptr;  // SPIR-V words; copied, may be freed after the call.
    uint64_t spirvSize = 0;       // In bytes, a multiple of 4.
    const char* entryPoint = "main";
    const DescriptorSetDesc* sets = nullptr;
    uint32_t setsNum = 0;
    uint32_t pushConstantsSize = 0; // (Optional) Bytes, at offset 0, for CmdPushConstants.
    const char* name = nullptr;     // (Optional)
};

// Capacity of a descriptor pool: how many sets, and how many descriptors of each type in all.
struct DescriptorPoolDesc
{
    uint32_t setsMaxNum = 0;
    uint32_t descriptorsMaxNum[(size_t)DescriptorType::MAX_NUM] = {}; // Indexed by DescriptorType.
};

// One descriptor written into a set. Fields that do not apply to 'type' are ignored.
struct DescriptorWrite
{
    uint32_t binding = 0;
    uint32_t arrayElement = 0;
    DescriptorType type = DescriptorType::MAX_NUM;
    Texture* texture = nullptr; // SAMPLED_TEXTURE, STORAGE_TEXTURE.
    Buffer* buffer = nullptr;   // BUFFER, STORAGE_BUFFER, UNIFORM_BUFFER.
    uint64_t offset = 0;        // Buffers: bytes (uniform: a multiple of minUniformBufferOffsetAlignment).
    uint64_t range = 0;         // Buffers: bytes; 0 = to the end of the buffer.
    Sampler* sampler = nullptr; // SAMPLER (not immutable).
};

// ------------------------------------------------------------------------------------------------
// Synchronization
//
// A resource's state is what last touched it (Access) and, for textures, its Layout. A barrier
// from 'before' to 'after' waits for the 'before' accesses and makes their writes visible to the
// 'after' accesses. It is needed when either side writes (RAW, WAR, WAW) or when the layout
// changes; read-after-read in the same layout needs none. Pipeline stages are implied by the
// access bits (SHADER_* and UNIFORM: compute shader; INDIRECT_ARGUMENTS: indirect command read;
// COPY_*: transfer; HOST_*: host; UNKNOWN: any stage, any memory access).

enum AccessBits : uint32_t
{
    ACCESS_NONE = 0,                      // Not used yet (the texture's Layout is then UNDEFINED or known).
    ACCESS_SHADER_READ = 1 << 0,          // Sampled texture or read-only buffer, compute shader.
    ACCESS_SHADER_READ_WRITE = 1 << 1,    // Storage texture or storage buffer, compute shader.
    ACCESS_UNIFORM = 1 << 2,              // Uniform buffer, compute shader.
    ACCESS_INDIRECT_ARGUMENTS = 1 << 3,   // CmdDispatchIndirect.
    ACCESS_COPY_SOURCE = 1 << 4,
    ACCESS_COPY_DESTINATION = 1 << 5,     // Also CmdClearTexture, CmdFillBuffer.
    ACCESS_HOST_READ = 1 << 6,            // Map after the device wrote (readback).
    ACCESS_HOST_WRITE = 1 << 7,           // Map before the device reads (upload).
    ACCESS_UNKNOWN = 1u << 31,            // Anything, anywhere (resources coming from outside).
};

enum class Layout : uint32_t
{
    UNDEFINED,       // Content may be discarded.
    GENERAL,         // Storage textures.
    SHADER_RESOURCE, // Sampled textures.
    COPY_SOURCE,
    COPY_DESTINATION,
    COLOR_ATTACHMENT, // Only as a state of textures coming from / going back to a renderer.
    PRESENT,          // Only as a state of textures coming from / going back to a renderer.

    MAX_NUM
};

struct TextureState
{
    uint32_t access = ACCESS_NONE; // AccessBits.
    Layout layout = Layout::UNDEFINED;
};

struct TextureBarrier
{
    Texture* texture = nullptr;
    TextureState before = {};
    TextureState after = {};
};

struct BufferBarrier
{
    Buffer* buffer = nullptr;
    uint32_t before = ACCESS_NONE; // AccessBits.
    uint32_t after = ACCESS_NONE;
};

// Memory barrier for all resources (no layout change).
struct GlobalBarrier
{
    uint32_t before = ACCESS_NONE; // AccessBits.
    uint32_t after = ACCESS_NONE;
};

struct BarrierDesc
{
    const GlobalBarrier* globals = nullptr;
    uint32_t globalsNum = 0;
    const BufferBarrier* buffers = nullptr;
    uint32_t buffersNum = 0;
    const TextureBarrier* textures = nullptr;
    uint32_t texturesNum = 0;
};

// ------------------------------------------------------------------------------------------------
// Device

struct DeviceDesc
{
    const char* adapterName = "";            // Valid for the device's lifetime.
    bool isSoftware = false;                 // CPU implementation (lavapipe).
    bool timestampsSupported = false;        // CmdWriteTimestamp gives meaningful values.
    double timestampPeriodNs = 0.0;          // Nanoseconds per timestamp tick.
    bool storageTextureReadWithoutFormat = false;  // image2D without a format qualifier, loads.
    bool storageTextureWriteWithoutFormat = false; // image2D without a format qualifier, stores.
    uint64_t uniformBufferOffsetAlignment = 256;   // For DescriptorWrite::offset of uniform buffers.
    uint64_t storageBufferOffsetAlignment = 256;
    uint32_t uniformBufferMaxRange = 16384;        // Bytes visible through one uniform descriptor.
    uint32_t dispatchMaxNum[3] = {};               // Workgroups per dimension.
};

class Device
{
public:
    virtual ~Device() = default;

    virtual const DeviceDesc& GetDesc() const = 0;

    // True if 'format' can be created with all of 'usage' (TextureUsageBits).
    virtual bool IsTextureFormatSupported(Format format, uint32_t usage) const = 0;

    // Resources. 'out' is null on failure. Destroy* accept null.
    virtual Result CreateTexture(const TextureDesc& desc, Texture*& out) = 0;
    virtual void DestroyTexture(Texture* texture) = 0;
    virtual Result CreateBuffer(const BufferDesc& desc, Buffer*& out) = 0;
    virtual void DestroyBuffer(Buffer* buffer) = 0;
    virtual Result CreateSampler(const SamplerDesc& desc, Sampler*& out) = 0;
    virtual void DestroySampler(Sampler* sampler) = 0;

    // Descriptions of created objects (wrapped native textures report what they were given).
    virtual const TextureDesc& GetTextureDesc(const Texture& texture) const = 0;
    virtual const BufferDesc& GetBufferDesc(const Buffer& buffer) const = 0;
    // Bytes of device memory the resource occupies (its memory requirements); 0 for wrapped ones.
    virtual uint64_t GetTextureMemorySize(const Texture& texture) const = 0;
    virtual uint64_t GetBufferMemorySize(const Buffer& buffer) const = 0;

    // Host pointer to a HOST_UPLOAD / HOST_READBACK buffer, valid until the buffer is destroyed;
    // null for DEVICE buffers. Coherent: no flush needed, but order device writes before host
    // reads with a barrier to ACCESS_HOST_READ and a completed submission.
    virtual void* MapBuffer(Buffer& buffer) = 0;

    virtual Result CreateComputePipeline(const ComputePipelineDesc& desc, Pipeline*& out) = 0;
    virtual void DestroyPipeline(Pipeline* pipeline) = 0;

    virtual Result CreateDescriptorPool(const DescriptorPoolDesc& desc, DescriptorPool*& out) = 0;
    virtual void DestroyDescriptorPool(DescriptorPool* pool) = 0;
    // Frees every set allocated from 'pool'. The sets must no longer be in use by the device.
    virtual Result ResetDescriptorPool(DescriptorPool& pool) = 0;
    // A set with the layout of 'pipeline's set 'setIndex'. OUT_OF_MEMORY when the pool is full.
    virtual Result AllocateDescriptorSet(DescriptorPool& pool, const Pipeline& pipeline, uint32_t setIndex,
                                         DescriptorSet*& out) = 0;
    virtual void UpdateDescriptorSet(DescriptorSet& set, const DescriptorWrite* writes, uint32_t writesNum) = 0;

    // Timestamp queries: 'queryNum' slots.
    virtual Result CreateQueryPool(uint32_t queryNum, QueryPool*& out) = 0;
    virtual void DestroyQueryPool(QueryPool* pool) = 0;
    // Copies 'num' raw timestamps (ticks, masked to the queue's valid bits; multiply differences by
    // DeviceDesc::timestampPeriodNs) without waiting; NOT_READY if any is not available yet.
    virtual Result GetTimestamps(QueryPool& pool, uint32_t first, uint32_t num, uint64_t* outTicks) = 0;

    // Command buffers of the device's own queue (samples and tests; engines record into their own).
    virtual Result CreateCommandBuffer(CommandBuffer*& out) = 0;
    virtual void DestroyCommandBuffer(CommandBuffer* commandBuffer) = 0;
    // Starts recording (one-time submit); the buffer must not be in flight.
    virtual Result BeginCommandBuffer(CommandBuffer& commandBuffer) = 0;
    virtual Result EndCommandBuffer(CommandBuffer& commandBuffer) = 0;
    // Submits an ended command buffer to the device's queue and waits until it completed.
    virtual Result SubmitAndWait(CommandBuffer& commandBuffer) = 0;
    virtual Result WaitIdle() = 0;

    // Recording.
    virtual void CmdBarrier(CommandBuffer& cmd, const BarrierDesc& desc) = 0;
    virtual void CmdBindPipeline(CommandBuffer& cmd, const Pipeline& pipeline) = 0;
    // Binds 'set' at 'setIndex' of 'pipeline's layout (the set must have been allocated for it).
    virtual void CmdBindDescriptorSet(CommandBuffer& cmd, const Pipeline& pipeline, uint32_t setIndex,
                                      const DescriptorSet& set) = 0;
    virtual void CmdPushConstants(CommandBuffer& cmd, const Pipeline& pipeline, const void* data, uint32_t size) = 0;
    virtual void CmdDispatch(CommandBuffer& cmd, uint32_t x, uint32_t y, uint32_t z) = 0;
    // Reads 3 uint32 (x, y, z workgroups) at 'offset' (a multiple of 4) in 'buffer'.
    virtual void CmdDispatchIndirect(CommandBuffer& cmd, const Buffer& buffer, uint64_t offset) = 0;
    // 'texture' in COPY_DESTINATION or GENERAL layout. Integer formats get the values truncated.
    virtual void CmdClearTexture(CommandBuffer& cmd, Texture& texture, Layout layout, const float color[4]) = 0;
    // Fills 'size' bytes (a multiple of 4; 0 = to the end) at 'offset' with 'value'.
    virtual void CmdFillBuffer(CommandBuffer& cmd, Buffer& buffer, uint64_t offset, uint64_t size, uint32_t value) = 0;
    virtual void CmdCopyBuffer(CommandBuffer& cmd, Buffer& dst, uint64_t dstOffset, const Buffer& src,
                               uint64_t srcOffset, uint64_t size) = 0;
    // Whole texture <-> buffer, rows tightly packed (width * GetFormatBytesPerPixel bytes).
    // The texture is in COPY_DESTINATION (upload) or COPY_SOURCE (readback) layout.
    virtual void CmdCopyBufferToTexture(CommandBuffer& cmd, Texture& dst, const Buffer& src, uint64_t srcOffset) = 0;
    virtual void CmdCopyTextureToBuffer(CommandBuffer& cmd, Buffer& dst, uint64_t dstOffset, const Texture& src) = 0;
    // Queries must be reset (in this or an earlier submitted command buffer) before being written.
    virtual void CmdResetQueries(CommandBuffer& cmd, QueryPool& pool, uint32_t first, uint32_t num) = 0;
    // Writes the time at which all previously recorded commands completed.
    virtual void CmdWriteTimestamp(CommandBuffer& cmd, QueryPool& pool, uint32_t query) = 0;
    // (Optional for backends) Debug labels around a group of commands; no-ops without tools.
    virtual void CmdBeginLabel(CommandBuffer& cmd, const char* name) = 0;
    virtual void CmdEndLabel(CommandBuffer& cmd) = 0;
};

// Destroys a device created by a backend (e.g. CreateDeviceVulkan). Null is ignored. Every object
// created through it must have been destroyed first.
inline void DestroyDevice(Device* device)
{
    delete device;
}

} // namespace rhi
} // namespace nrd
