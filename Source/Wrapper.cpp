// Public entry points: argument checks, exception barrier, name tables.
#include "InstanceImpl.h"

#include <cstring>
#include <new>

namespace nrd
{

static_assert(NRD_VERSION_MAJOR == 0 && NRD_VERSION_MINOR == 1, "Wrapper.cpp does not match NRD.h");

static const Method kSupportedMethods[] = {Method::SIGMA_SHADOW, Method::SIGMA_SHADOW_TRANSLUCENCY, Method::REFERENCE,
                                           Method::TILED_SHADOW, Method::REBLUR_DIFFUSE, Method::REBLUR_SPECULAR,
                                           Method::REBLUR_DIFFUSE_SPECULAR, Method::REBLUR_DIFFUSE_OCCLUSION,
                                           Method::REBLUR_SPECULAR_OCCLUSION, Method::REBLUR_DIFFUSE_SPECULAR_OCCLUSION,
                                           Method::CONFIDENCE, Method::REFLECTION, Method::RELAX_DIFFUSE, Method::RELAX_SPECULAR,
                                           Method::RELAX_DIFFUSE_SPECULAR};
static_assert(sizeof(kSupportedMethods) / sizeof(kSupportedMethods[0]) == size_t(Method::MAX_NUM),
              "every method must be listed");

static const char* const kResultNames[] = {"SUCCESS", "FAILURE", "INVALID_ARGUMENT", "UNSUPPORTED", "NON_UNIQUE_IDENTIFIER"};
static_assert(sizeof(kResultNames) / sizeof(kResultNames[0]) == size_t(Result::MAX_NUM), "name table");

static const char* const kMethodNames[] = {"SIGMA_SHADOW", "SIGMA_SHADOW_TRANSLUCENCY", "REFERENCE", "TILED_SHADOW",
    "REBLUR_DIFFUSE", "REBLUR_SPECULAR", "REBLUR_DIFFUSE_SPECULAR", "REBLUR_DIFFUSE_OCCLUSION", "REBLUR_SPECULAR_OCCLUSION",
    "REBLUR_DIFFUSE_SPECULAR_OCCLUSION", "CONFIDENCE", "REFLECTION", "RELAX_DIFFUSE", "RELAX_SPECULAR", "RELAX_DIFFUSE_SPECULAR"};
static_assert(sizeof(kMethodNames) / sizeof(kMethodNames[0]) == size_t(Method::MAX_NUM), "name table");

static const char* const kResourceTypeNames[] = {"IN_MV", "IN_NORMAL_ROUGHNESS", "IN_VIEWZ", "IN_SHADOWDATA",
    "IN_SHADOW_TRANSLUCENCY", "IN_RADIANCE", "IN_SHADOW_VISIBILITY", "IN_SHADOW_BITMASK", "IN_DIFF_RADIANCE_HITDIST",
    "IN_SPEC_RADIANCE_HITDIST", "IN_DIFF_HITDIST", "IN_SPEC_HITDIST", "IN_DIFF_CONFIDENCE", "IN_SPEC_CONFIDENCE", "IN_GRADIENTS",
    "OUT_SHADOW_TRANSLUCENCY", "OUT_RADIANCE", "OUT_DIFF_RADIANCE_HITDIST", "OUT_SPEC_RADIANCE_HITDIST",
    "OUT_DIFF_HITDIST", "OUT_SPEC_HITDIST", "OUT_DIFF_CONFIDENCE", "OUT_SPEC_CONFIDENCE", "TRANSIENT_POOL", "PERMANENT_POOL", "BUFFER_POOL"};
static_assert(sizeof(kResourceTypeNames) / sizeof(kResourceTypeNames[0]) == size_t(ResourceType::MAX_NUM), "name table");

static const char* const kFormatNames[] = {"R8_UNORM", "RG8_UNORM", "RGBA8_UNORM", "R16_SFLOAT", "RG16_SFLOAT",
    "RGBA16_SFLOAT", "R32_SFLOAT", "RG32_SFLOAT", "RGBA32_SFLOAT", "R32_UINT", "RG32_UINT", "R10_G10_B10_A2_UNORM",
    "R11_G11_B10_UFLOAT"};
static_assert(sizeof(kFormatNames) / sizeof(kFormatNames[0]) == size_t(Format::MAX_NUM), "name table");

static const uint8_t kFormatBytes[] = {1, 2, 4, 2, 4, 8, 4, 8, 16, 4, 8, 4, 4};
static_assert(sizeof(kFormatBytes) == size_t(Format::MAX_NUM), "size table");

// The instance itself lives in application memory too when callbacks are given.
static InstanceImpl* NewInstance(const DenoiserCreationDesc& desc)
{
    const AllocationCallbacks& a = desc.allocationCallbacks;
    bool custom = a.Allocate && a.Free && a.Reallocate;
    void* memory = custom ? a.Allocate(a.userArg, sizeof(InstanceImpl), alignof(InstanceImpl))
                          : ::operator new(sizeof(InstanceImpl), std::nothrow);
    if (!memory)
        return nullptr;
    try
    {
        return new (memory) InstanceImpl(desc);
    }
    catch (...)
    {
        custom ? a.Free(a.userArg, memory) : ::operator delete(memory);
        return nullptr;
    }
}

static void DeleteInstance(InstanceImpl* instance)
{
    if (!instance)
        return;
    const AllocationCallbacks* a = instance->Allocator();
    AllocationCallbacks callbacks = a ? *a : AllocationCallbacks{};
    instance->~InstanceImpl();
    if (a)
        callbacks.Free(callbacks.userArg, instance);
    else
        ::operator delete(instance);
}

const LibraryDesc& GetLibraryDesc()
{
    static const LibraryDesc desc = [] {
        LibraryDesc d;
        d.supportedMethods = kSupportedMethods;
        d.supportedMethodsNum = uint32_t(Method::MAX_NUM);
        d.versionMajor = NRD_VERSION_MAJOR;
        d.versionMinor = NRD_VERSION_MINOR;
        d.versionBuild = NRD_VERSION_BUILD;
        return d;
    }();
    return desc;
}

Result CreateDenoiser(const DenoiserCreationDesc& desc, Denoiser*& outDenoiser)
{
    outDenoiser = nullptr;
    InstanceImpl* instance = nullptr;
    try
    {
        instance = NewInstance(desc);
        if (!instance)
            return Result::FAILURE;
        Result result = instance->Create(desc);
        if (result != Result::SUCCESS)
        {
            DeleteInstance(instance);
            return result;
        }
    }
    catch (...)
    {
        DeleteInstance(instance);
        return Result::FAILURE;
    }
    outDenoiser = reinterpret_cast<Denoiser*>(instance);
    return Result::SUCCESS;
}

const DenoiserDesc& GetDenoiserDesc(const Denoiser& denoiser)
{
    return reinterpret_cast<const InstanceImpl&>(denoiser).GetDesc();
}

Result SetCommonSettings(Denoiser& denoiser, const CommonSettings& settings)
{
    try
    {
        return reinterpret_cast<InstanceImpl&>(denoiser).SetCommonSettings(settings);
    }
    catch (...)
    {
        return Result::FAILURE;
    }
}

static Result SetSettings(Denoiser& denoiser, Identifier identifier, SettingsKind kind, const void* settings)
{
    try
    {
        return reinterpret_cast<InstanceImpl&>(denoiser).SetMethodSettings(identifier, kind, settings);
    }
    catch (...)
    {
        return Result::FAILURE;
    }
}

Result SetMethodSettings(Denoiser& denoiser, Identifier identifier, const SigmaSettings& settings)
{
    return SetSettings(denoiser, identifier, SettingsKind::SIGMA, &settings);
}

Result SetMethodSettings(Denoiser& denoiser, Identifier identifier, const ReferenceSettings& settings)
{
    return SetSettings(denoiser, identifier, SettingsKind::REFERENCE, &settings);
}

Result SetMethodSettings(Denoiser& denoiser, Identifier identifier, const TiledShadowSettings& settings)
{
    return SetSettings(denoiser, identifier, SettingsKind::TILED_SHADOW, &settings);
}

Result ValidateHitDistanceParameters(const HitDistanceParameters& parameters, LogCallback logCallback, void* logUserArg)
{
    return ValidateHitDistanceParameters(parameters, "HitDistanceParameters", Logger(logCallback, logUserArg));
}

Result SetMethodSettings(Denoiser& denoiser, Identifier identifier, const ReblurSettings& settings)
{
    return SetSettings(denoiser, identifier, SettingsKind::REBLUR, &settings);
}

Result SetMethodSettings(Denoiser& denoiser, Identifier identifier, const ConfidenceSettings& settings)
{
    return SetSettings(denoiser, identifier, SettingsKind::CONFIDENCE, &settings);
}

Result SetMethodSettings(Denoiser& denoiser, Identifier identifier, const ReflectionSettings& settings)
{
    return SetSettings(denoiser, identifier, SettingsKind::REFLECTION, &settings);
}

Result SetMethodSettings(Denoiser& denoiser, Identifier identifier, const RelaxSettings& settings)
{
    return SetSettings(denoiser, identifier, SettingsKind::RELAX, &settings);
}

Result GetComputeDispatches(Denoiser& denoiser, const Identifier* identifiers, uint32_t identifiersNum,
                            const DispatchDesc*& outDispatches, uint32_t& outDispatchesNum)
{
    return GetComputeDispatches(denoiser, identifiers, identifiersNum, DispatchStage::ALL, outDispatches,
                                outDispatchesNum);
}

Result GetComputeDispatches(Denoiser& denoiser, const Identifier* identifiers, uint32_t identifiersNum,
                            DispatchStage stage, const DispatchDesc*& outDispatches, uint32_t& outDispatchesNum)
{
    try
    {
        return reinterpret_cast<InstanceImpl&>(denoiser).GetComputeDispatches(identifiers, identifiersNum, stage,
                                                                               outDispatches, outDispatchesNum);
    }
    catch (...)
    {
        outDispatches = nullptr;
        outDispatchesNum = 0;
        return Result::FAILURE;
    }
}

void DestroyDenoiser(Denoiser* denoiser)
{
    DeleteInstance(reinterpret_cast<InstanceImpl*>(denoiser));
}

const char* GetResultString(Result result)
{
    return uint32_t(result) < uint32_t(Result::MAX_NUM) ? kResultNames[uint32_t(result)] : "UNKNOWN";
}

const char* GetMethodString(Method method)
{
    return uint32_t(method) < uint32_t(Method::MAX_NUM) ? kMethodNames[uint32_t(method)] : "UNKNOWN";
}

const char* GetResourceTypeString(ResourceType type)
{
    return uint32_t(type) < uint32_t(ResourceType::MAX_NUM) ? kResourceTypeNames[uint32_t(type)] : "UNKNOWN";
}

const char* GetFormatString(Format format)
{
    return uint32_t(format) < uint32_t(Format::MAX_NUM) ? kFormatNames[uint32_t(format)] : "UNKNOWN";
}

bool GetMethodFromString(const char* name, Method& outMethod)
{
    if (!name)
        return false;
    for (uint32_t i = 0; i < uint32_t(Method::MAX_NUM); i++)
        if (strcmp(name, kMethodNames[i]) == 0)
        {
            outMethod = Method(i);
            return true;
        }
    return false;
}

uint32_t GetFormatBytesPerPixel(Format format)
{
    return uint32_t(format) < uint32_t(Format::MAX_NUM) ? kFormatBytes[uint32_t(format)] : 0;
}

} // namespace nrd
