// Plain-data descriptions exchanged with the application. No graphics API types.
#pragma once

#include <cstdint>

#ifndef NRD_VERSION_MAJOR
#  error "Include NRD.h instead of NRDDescs.h"
#endif

namespace nrd
{

static_assert(NRD_VERSION_MAJOR == 0 && NRD_VERSION_MINOR == 1, "NRDDescs.h does not match NRD.h");

struct Denoiser; // Opaque instance.

// Application-chosen name of one method inside a denoiser (e.g. one per light). Must be unique.
typedef uint32_t Identifier;

enum class Result : uint32_t
{
    SUCCESS,
    FAILURE,               // Internal failure (out of memory).
    INVALID_ARGUMENT,      // Bad input; see the log callback for details. State is unchanged.
    UNSUPPORTED,           // Valid but not supported by this build.
    NON_UNIQUE_IDENTIFIER, // Two methods of one denoiser share an identifier.

    MAX_NUM
};

enum class Method : uint32_t
{
    // Shadow from one light: IN_NORMAL_ROUGHNESS, IN_VIEWZ, IN_MV (optional motion), IN_SHADOWDATA
    // -> OUT_SHADOW_TRANSLUCENCY (.x). Penumbra-driven spatial blur plus temporal stabilization.
    SIGMA_SHADOW,

    // As SIGMA_SHADOW plus IN_SHADOW_TRANSLUCENCY (.x shadow, .yzw translucency / multi-light
    // weighted visibility) -> OUT_SHADOW_TRANSLUCENCY (.x shadow, .yzw translucency).
    SIGMA_SHADOW_TRANSLUCENCY,

    // Plain accumulation of IN_RADIANCE into OUT_RADIANCE (ground truth for a still camera).
    REFERENCE,

    // Shadow from one light traced at 1 ray per pixel, tile-classified (document 000):
    // IN_SHADOW_VISIBILITY (or IN_SHADOW_BITMASK, see TiledShadowSettings::isBitmaskInput),
    // IN_VIEWZ, IN_NORMAL_ROUGHNESS, IN_MV -> OUT_SHADOW_TRANSLUCENCY (.x = denoised visibility).
    // 8x4-pixel bitmask tiles, 17x17 local moments, reprojection with neighbourhood clamping, three
    // edge-avoiding a-trous passes; tiles without spatial variance are skipped.
    TILED_SHADOW,

    // Recurrent-blur radiance denoiser (document 004, REBLUR), 0.5-1 ray per pixel: IN_MV,
    // IN_NORMAL_ROUGHNESS, IN_VIEWZ, IN_DIFF_RADIANCE_HITDIST and / or IN_SPEC_RADIANCE_HITDIST
    // (optional IN_DIFF_CONFIDENCE / IN_SPEC_CONFIDENCE, see ReblurSettings::isConfidenceInput)
    // -> OUT_DIFF_RADIANCE_HITDIST / OUT_SPEC_RADIANCE_HITDIST (.w = denoised normalized hit
    // distance). Settings: ReblurSettings. Shaders/Reblur/README.md lists passes and memory.
    REBLUR_DIFFUSE,
    REBLUR_SPECULAR,
    REBLUR_DIFFUSE_SPECULAR,

    // Occlusion only: IN_DIFF_HITDIST / IN_SPEC_HITDIST -> OUT_DIFF_HITDIST / OUT_SPEC_HITDIST (.x =
    // denoised normalized hit distance: ambient / specular occlusion).
    REBLUR_DIFFUSE_OCCLUSION,
    REBLUR_SPECULAR_OCCLUSION,
    REBLUR_DIFFUSE_SPECULAR_OCCLUSION,

    // History confidence from sparse temporal gradients (document 003): IN_GRADIENTS (1/3
    // resolution), IN_VIEWZ, IN_NORMAL_ROUGHNESS, IN_MV -> OUT_DIFF_CONFIDENCE / OUT_SPEC_CONFIDENCE
    // (full resolution, ready to be bound as IN_DIFF_CONFIDENCE / IN_SPEC_CONFIDENCE of REBLUR or
    // RELAX). Edge-aware a-trous filtering of the gradients, normalization, conversion to [0, 1]
    // and a short temporal filter. Settings: ConfidenceSettings. Shaders/Confidence/README.md.
    CONFIDENCE,
    // Glossy reflections traced at a variable rate, FidelityFX-style (documents 000 and 002): IN_MV,
    // IN_NORMAL_ROUGHNESS, IN_VIEWZ, IN_SPEC_RADIANCE_HITDIST -> OUT_SPEC_RADIANCE_HITDIST. Runs in
    // two stages around the application's ray pass (DispatchStage): CLASSIFICATION decides per
    // pixel whether it traces a ray (1, 2 or 4 per 2x2 quad, more where the temporal variance is
    // high, always on mirrors) and writes the ray list, the ray counter and the indirect arguments
    // (BufferDesc::content); the application traces exactly the listed rays, writing
    // IN_SPEC_RADIANCE_HITDIST at each ray's pixel and at the quad neighbours its entry names;
    // DENOISING runs reprojection, spatial, temporal and blur passes on the 8x8 tiles that need
    // them only. Settings: ReflectionSettings. Shaders/Reflection/README.md lists passes and memory.
    REFLECTION,

    // SVGF-style radiance denoisers with fast-history clamping (document 004, RELAX): temporal
    // accumulation into a slow and a fast history, history fix, clamping of the slow history to the
    // fast one, variance estimation and edge-stopping a-trous iterations; see RelaxSettings.
    // RELAX_DIFFUSE: IN_DIFF_RADIANCE_HITDIST -> OUT_DIFF_RADIANCE_HITDIST. RELAX_SPECULAR:
    // IN_SPEC_RADIANCE_HITDIST -> OUT_SPEC_RADIANCE_HITDIST. RELAX_DIFFUSE_SPECULAR: both. All take
    // IN_MV, IN_NORMAL_ROUGHNESS, IN_VIEWZ, and IN_DIFF_CONFIDENCE / IN_SPEC_CONFIDENCE when
    // RelaxSettings::useConfidenceInputs.
    RELAX_DIFFUSE,
    RELAX_SPECULAR,
    RELAX_DIFFUSE_SPECULAR,

    MAX_NUM
};

// Part of a frame GetComputeDispatches produces. A method whose application traces rays between
// its dispatches (REFLECTION) has a CLASSIFICATION part (before the ray pass) and a DENOISING part
// (after it); every other method runs in DENOISING only. ALL is both, in order.
enum class DispatchStage : uint8_t
{
    ALL,
    CLASSIFICATION,
    DENOISING,

    MAX_NUM
};

// Pool texture formats. Storage formats used by the shaders; the application may create its own
// input textures in any format it can sample as float (or uint for *_UINT).
enum class Format : uint32_t
{
    R8_UNORM,
    RG8_UNORM,
    RGBA8_UNORM,
    R16_SFLOAT,
    RG16_SFLOAT,
    RGBA16_SFLOAT,
    R32_SFLOAT,
    RG32_SFLOAT,
    RGBA32_SFLOAT,
    R32_UINT,
    RG32_UINT,
    R10_G10_B10_A2_UNORM,
    R11_G11_B10_UFLOAT,

    MAX_NUM
};

enum class DescriptorType : uint32_t
{
    TEXTURE,         // Sampled image (read-only), set 0.
    STORAGE_TEXTURE, // Storage image (read-write), set 0.
    BUFFER,          // Storage buffer, read-only, set 0.
    STORAGE_BUFFER,  // Storage buffer, read-write, set 0.

    MAX_NUM
};

enum class Sampler : uint32_t
{
    NEAREST_CLAMP,
    LINEAR_CLAMP,

    MAX_NUM
};

// What a dispatch resource refers to: an application texture (IN_* / OUT_*), or a pool entry.
// Formats in brackets are the recommended minimum precision of application textures.
enum class ResourceType : uint32_t
{
    // [RG16f+ or RGBA16f+] Non-jittered surface motion, uvPrev = uv + mv.xy * motionVectorScale.xy
    // (2D), or world-space motion (3D), posPrev = pos + mv.xyz * motionVectorScale, see
    // CommonSettings::isMotionVectorInWorldSpace. Always bound; with motionVectorScale = 0 only
    // the camera motion (from the matrices) is tracked.
    IN_MV,

    // [RGBA8+ or RGB10A2+] .xyz world-space normal encoded as n * 0.5 + 0.5, .w linear roughness.
    IN_NORMAL_ROUGHNESS,

    // [R32f] Linear view-space depth, positive in front of the camera. |viewZ| > denoisingRange
    // (or +Inf) marks sky: such pixels are not denoised and not written.
    IN_VIEWZ,

    // [RG16f+] SIGMA shadow input: .x shadow visibility in [0, 1], .y penumbra data, as produced by
    // SIGMA_FrontEnd_PackShadow (Shaders/Include/NRD.glsl).
    IN_SHADOWDATA,

    // [RGBA8+] SIGMA_SHADOW_TRANSLUCENCY input: .x shadow, .yzw translucency, as produced by
    // SIGMA_FrontEnd_MultiLightEnd or SIGMA_FrontEnd_PackShadow with translucency.
    IN_SHADOW_TRANSLUCENCY,

    // [RGBA16f+ or RGBA32f] REFERENCE input: any linear signal, all four channels accumulated.
    IN_RADIANCE,

    // [R8+] TILED_SHADOW input: 1-spp shadow visibility, 1 = lit, 0 = shadowed (values >= 0.5 and
    // NaN count as lit). Read by the prepare pass only.
    IN_SHADOW_VISIBILITY,

    // [R32_UINT] TILED_SHADOW input written directly by the application's ray pass instead of
    // IN_SHADOW_VISIBILITY (TiledShadowSettings::isBitmaskInput): DivideUp(width, 8) x
    // DivideUp(height, 4) texels, texel (x / 8, y / 4) has bit (x % 8) + 8 * (y % 4) set when pixel
    // (x, y) is lit. Bits of pixels outside the image are ignored (write them as lit).
    IN_SHADOW_BITMASK,

    // Radiance + hit distance denoisers (REBLUR, RELAX). Hit distances are normalized: see
    // HitDistanceParameters (NRDSettings.h) and REBLUR_FrontEnd_GetNormHitDist (NRD.glsl).

    // [RGBA16f+] Noisy diffuse / specular signal: .rgb radiance (linear, >= 0), .w normalized hit
    // distance in [0, 1] (1 = nothing hit), as packed by REBLUR_FrontEnd_PackRadianceAndNormHitDist.
    // Specular radiance is demodulated by the application's specular albedo, diffuse by its albedo.
    IN_DIFF_RADIANCE_HITDIST,
    IN_SPEC_RADIANCE_HITDIST,

    // [R16f+] Occlusion variants: .x normalized hit distance only (REBLUR_FrontEnd_GetNormHitDist).
    IN_DIFF_HITDIST,
    IN_SPEC_HITDIST,

    // [R8+] (Optional) Confidence of the history per pixel, .x in [0, 1]: 1 = history valid, 0 =
    // history invalid (lighting changed); values in between shorten the history (the history length
    // is multiplied by it; REBLUR diffuse and RELAX keep at least 4 frames, which their clamps and
    // anti-lag move to the new lighting; Shaders/Confidence/README.md). Non-finite values count as 1.
    IN_DIFF_CONFIDENCE,
    IN_SPEC_CONFIDENCE,

    // [RGBA16f+] CONFIDENCE input: sparse temporal gradients of luminance, one texel per 3x3 pixel
    // stratum (texel (x, y) covers pixels 3x..3x+2, 3y..3y+2; at least DivideUp(width, 3) x
    // DivideUp(height, 3) texels, larger textures are fine). .x |diffuse luminance difference|
    // between this and the previous frame for the same surface and light sample, .y the larger of
    // the two diffuse luminances, .z / .w the same for specular. All 0 where a stratum has no
    // gradient (no pixel with valid history). Non-finite or negative values count as 0.
    IN_GRADIENTS,

    // [R8+ for SIGMA_SHADOW, RGBA8+ for SIGMA_SHADOW_TRANSLUCENCY] Denoised shadow; decode with
    // SIGMA_BackEnd_UnpackShadow. TILED_SHADOW writes the denoised visibility in [0, 1] to every
    // channel (read .x); sky pixels are not written.
    OUT_SHADOW_TRANSLUCENCY,

    // [RGBA16f+ or RGBA32f] REFERENCE output: running mean of IN_RADIANCE.
    OUT_RADIANCE,

    // [RGBA16f+] Denoised diffuse / specular radiance in .rgb (demodulated as the input), denoised
    // normalized hit distance in .w; decode with REBLUR_BackEnd_UnpackRadianceAndNormHitDist. Sky
    // pixels are not written.
    OUT_DIFF_RADIANCE_HITDIST,
    OUT_SPEC_RADIANCE_HITDIST,

    // [R16f+] Occlusion variants: .x denoised normalized hit distance in [0, 1], i.e. the ambient
    // (diffuse) or specular occlusion. Sky pixels are not written.
    OUT_DIFF_HITDIST,
    OUT_SPEC_HITDIST,

    // [R8+] CONFIDENCE outputs: .x history confidence in [0, 1] (1 = lighting unchanged, 0 =
    // lighting changed, history invalid), in the format IN_DIFF_CONFIDENCE / IN_SPEC_CONFIDENCE
    // expect. Sky pixels are not written.
    OUT_DIFF_CONFIDENCE,
    OUT_SPEC_CONFIDENCE,

    // Pool entries: ResourceDesc::indexInPool indexes DenoiserDesc::transientPool / permanentPool /
    // buffers.
    TRANSIENT_POOL,
    PERMANENT_POOL,
    BUFFER_POOL,

    MAX_NUM
};

// Application memory hooks (optional). All three must be set, or none.
struct AllocationCallbacks
{
    void* (*Allocate)(void* userArg, size_t size, size_t alignment) = nullptr;
    void* (*Reallocate)(void* userArg, void* memory, size_t size, size_t alignment) = nullptr;
    void (*Free)(void* userArg, void* memory) = nullptr;
    void* userArg = nullptr;
};

enum class LogSeverity : uint32_t
{
    INFO,
    WARNING,
    ERROR,
};

// (Optional) Receives one readable, zero-terminated line per problem, e.g. why INVALID_ARGUMENT.
typedef void (*LogCallback)(void* userArg, LogSeverity severity, const char* message);

struct MethodDesc
{
    Identifier identifier = 0;
    Method method = Method::MAX_NUM;
};

struct DenoiserCreationDesc
{
    const MethodDesc* methods = nullptr; // 'methodsNum' entries, at least one.
    uint32_t methodsNum = 0;
    uint16_t renderWidth = 0;  // Pool texture size in pixels, 1..16384. Frames may use any
    uint16_t renderHeight = 0; // smaller size (CommonSettings::resourceSize) without re-creation.
    AllocationCallbacks allocationCallbacks = {}; // (Optional)
    LogCallback logCallback = nullptr;            // (Optional)
    void* logUserArg = nullptr;                   // (Optional) passed to 'logCallback'.
};

// Binding model of every pipeline (Vulkan terms; other APIs map 'set' to a register space):
//   set 'resourcesSetIndex': the dispatch's resources, binding i = i-th resource of the dispatch;
//   set 'constantsSetIndex': binding 'constantBufferBinding' = uniform block (std140),
//                            bindings 'samplersBaseBinding' + i = static sampler i (immutable).
struct SpirvBindingDesc
{
    uint32_t resourcesSetIndex = 0;
    uint32_t constantsSetIndex = 1;
    uint32_t constantBufferBinding = 0;
    uint32_t samplersBaseBinding = 1;
};

struct LibraryDesc
{
    SpirvBindingDesc spirvBinding = {};
    const Method* supportedMethods = nullptr; // Static storage.
    uint32_t supportedMethodsNum = 0;
    uint8_t versionMajor = 0;
    uint8_t versionMinor = 0;
    uint8_t versionBuild = 0;
    // Normal encoding expected in IN_NORMAL_ROUGHNESS: 0 = n * 0.5 + 0.5 (xyz), roughness linear.
    uint8_t normalEncoding = 0;
};

struct ResourceRangeDesc
{
    DescriptorType descriptorType = DescriptorType::MAX_NUM;
    uint32_t baseBinding = 0;    // First binding in the resources set.
    uint32_t descriptorsNum = 0; // Consecutive bindings of this type.
};

struct ComputeShaderDesc
{
    const void* bytecode = nullptr; // SPIR-V words, static storage.
    uint64_t size = 0;              // In bytes.
};

struct PipelineDesc
{
    ComputeShaderDesc spirv = {};
    const char* entryPointName = "main";
    const char* shaderIdentifier = nullptr;        // Readable, e.g. "Sigma_Blur".
    const ResourceRangeDesc* resourceRanges = nullptr; // In binding order.
    uint32_t resourceRangesNum = 0;
    uint32_t constantBufferSize = 0; // Bytes of this pipeline's uniform block (0 if none); every
                                     // dispatch of it carries exactly this many constant bytes.
    bool hasConstantData = false;
    uint16_t groupSizeX = 0; // Workgroup size declared by the shader.
    uint16_t groupSizeY = 0;
};

// Pool texture: size = DivideUp(renderWidth, downsampleX) x DivideUp(renderHeight, downsampleY),
// one mip level, usage sampled + storage.
struct TextureDesc
{
    Format format = Format::MAX_NUM;
    uint16_t downsampleX = 1;
    uint16_t downsampleY = 1;
};

// What a pool buffer holds, for the application's ray pass (REFLECTION); PRIVATE buffers are the
// method's own business.
//   RAY_LIST: one uint32 per ray, in [0, ray count): bits 0..13 pixel x, bits 14..27 pixel y,
//     bit 28: also write the result to the horizontal quad neighbour (x ^ 1, y), bit 29: to the
//     vertical one (x, y ^ 1), bit 30: to the diagonal one (x ^ 1, y ^ 1). Bit 31 is 0.
//   RAY_COUNTERS (also indirect arguments): uint32 words
//     [0..2] indirect dispatch of the ray pass: (DivideUp(ray count, 64), 1, 1), 64 rays per group;
//     [3]    ray count;
//     [4..6] indirect dispatch of the denoising passes (tile count, 1, 1), used by the method;
//     [7]    count of 8x8 tiles that need the denoiser; [8..] private.
// Written by the CLASSIFICATION stage of the frame, valid until the next one.
enum class BufferContent : uint8_t
{
    PRIVATE,
    RAY_LIST,
    RAY_COUNTERS,

    MAX_NUM
};

// Pool buffer: 'size' bytes, usage storage (+ indirect arguments if 'isIndirectArguments').
// 'isPermanent' buffers keep their content across frames (zero them at creation); the content of
// the others is undefined at the start of a frame: methods clear what they rely on themselves.
struct BufferDesc
{
    uint64_t size = 0;
    bool isIndirectArguments = false;
    bool isPermanent = false;
    BufferContent content = BufferContent::PRIVATE;
    Identifier identifier = 0; // Method that owns the buffer.
};

struct DescriptorPoolDesc
{
    // Resource sets (set 0) of one frame of all methods (each dispatch once). The constants +
    // samplers set (set 1) is not counted: one per pipeline suffices with a dynamic uniform
    // offset, else allocate one per dispatch as well.
    uint32_t setsMaxNum = 0;
    uint32_t constantBuffersMaxNum = 0;
    uint32_t texturesMaxNum = 0;         // Sampled images.
    uint32_t storageTexturesMaxNum = 0;  // Storage images.
    uint32_t buffersMaxNum = 0;          // Storage buffers (read-only and read-write).
    uint32_t samplersMaxNum = 0;         // Immutable samplers (in the per-pipeline constants sets).
};

struct DenoiserDesc
{
    const PipelineDesc* pipelines = nullptr; // Deduplicated across methods.
    uint32_t pipelinesNum = 0;
    const Sampler* samplers = nullptr; // Static samplers, binding samplersBaseBinding + i.
    uint32_t samplersNum = 0;
    const TextureDesc* permanentPool = nullptr; // History; owned by the denoiser across frames.
    uint32_t permanentPoolSize = 0;
    const TextureDesc* transientPool = nullptr; // Free for the application after the dispatches.
    uint32_t transientPoolSize = 0;             // Shared between methods where format and size match.
    const BufferDesc* buffers = nullptr;
    uint32_t buffersNum = 0;
    uint32_t constantBufferMaxDataSize = 0; // Largest uniform block of any dispatch, in bytes.
    DescriptorPoolDesc descriptorPoolDesc = {};
    uint16_t renderWidth = 0; // As created.
    uint16_t renderHeight = 0;
};

struct ResourceDesc
{
    DescriptorType descriptorType = DescriptorType::MAX_NUM;
    ResourceType type = ResourceType::MAX_NUM;
    uint16_t indexInPool = 0; // For *_POOL types; 0 otherwise.
};

struct DispatchDesc
{
    const char* name = nullptr;   // Readable, e.g. "SIGMA_SHADOW - Blur". Static storage.
    Identifier identifier = 0;    // Method this dispatch belongs to.
    uint16_t pipelineIndex = 0;   // Into DenoiserDesc::pipelines.
    const ResourceDesc* resources = nullptr; // In binding order; matches the pipeline's ranges.
    uint32_t resourcesNum = 0;
    const uint8_t* constantBufferData = nullptr; // std140 block, 'constantBufferDataSize' bytes.
    uint32_t constantBufferDataSize = 0;
    uint16_t gridWidth = 0;  // Workgroups in X and Y (already rounded up).
    uint16_t gridHeight = 0;
    // (Optional) Indirect dispatch: if 'isIndirect', the grid comes from 3 uint32 at
    // 'indirectArgumentsOffset' in buffer 'indirectArgumentsBuffer' (BUFFER_POOL index);
    // gridWidth / gridHeight are then the upper bound.
    bool isIndirect = false;
    uint16_t indirectArgumentsBuffer = 0;
    uint32_t indirectArgumentsOffset = 0;
};

} // namespace nrd
