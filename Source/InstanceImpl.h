// Internal: the denoiser instance, the builder methods use at creation, and the per-frame context.
#pragma once

#include "NRD.h"
#include "PassDecl.h"

#include <cstring>
#include <memory>
#include <new>
#include <string>
#include <vector>

namespace nrd
{

inline uint32_t DivideUp(uint32_t x, uint32_t y) { return (x + y - 1) / y; }

// Routes container memory through the application's AllocationCallbacks (or operator new).
template <class T>
struct StdAllocator
{
    using value_type = T;
    const AllocationCallbacks* callbacks = nullptr;

    StdAllocator() = default;
    explicit StdAllocator(const AllocationCallbacks* c) : callbacks(c) {}
    template <class U>
    StdAllocator(const StdAllocator<U>& other) : callbacks(other.callbacks) {}

    T* allocate(size_t n)
    {
        void* p = callbacks ? callbacks->Allocate(callbacks->userArg, n * sizeof(T), alignof(T)) : ::operator new(n * sizeof(T));
        if (!p)
            throw std::bad_alloc();
        return static_cast<T*>(p);
    }
    void deallocate(T* p, size_t)
    {
        if (callbacks)
            callbacks->Free(callbacks->userArg, p);
        else
            ::operator delete(p);
    }
    template <class U>
    bool operator==(const StdAllocator<U>& o) const { return callbacks == o.callbacks; }
    template <class U>
    bool operator!=(const StdAllocator<U>& o) const { return callbacks != o.callbacks; }
};

template <class T>
using Vector = std::vector<T, StdAllocator<T>>;

// Routes readable messages to the application's log callback (if any).
class Logger
{
public:
    Logger() = default;
    Logger(LogCallback callback, void* userArg) : m_Callback(callback), m_UserArg(userArg) {}
    void Error(const char* format, ...) const
#if defined(__GNUC__)
        __attribute__((format(printf, 2, 3)))
#endif
        ;

private:
    LogCallback m_Callback = nullptr;
    void* m_UserArg = nullptr;
};

// A resource of a dispatch as a method names it: an application texture or a pool entry whose
// index is local to the method until the instance finalizes the pools.
struct ResourceRef
{
    ResourceType type = ResourceType::MAX_NUM;
    uint16_t index = 0;
};

inline ResourceRef App(ResourceType type) { return {type, 0}; }

struct DispatchTemplate
{
    const char* name = nullptr;
    uint16_t pipelineIndex = 0;
    uint32_t firstResource = 0; // Into InstanceImpl::m_Resources.
    uint32_t resourcesNum = 0;
    uint32_t constantsSize = 0;
    uint16_t groupX = 0, groupY = 0;
};

class InstanceImpl;

// Per-frame values derived once from CommonSettings (double precision where it matters).
struct FrameData
{
    CommonSettings common = {};
    uint32_t width = 0, height = 0; // Resource size this frame.
    bool resetHistory = true;
    glsl::mat4 viewToWorld = {}, worldToClipPrev = {}, worldToViewPrev = {}, viewToClip = {};
    glsl::vec4 frustum = {};
    // Current clip -> previous clip (inverse(viewToClip * worldToView), then viewToClipPrev *
    // worldToViewPrev), formed in double precision; identity and false if viewToClip is singular.
    glsl::mat4 clipToClipPrev = {};
    bool isClipToClipPrevValid = false;
    float viewZSign = 1.0f;
    float projectY = 1.0f;
};

class FrameContext
{
public:
    FrameContext(InstanceImpl& instance, uint32_t methodIndex, const FrameData& frame)
        : m_Instance(instance), m_MethodIndex(methodIndex), m_Frame(frame) {}

    const FrameData& Frame() const { return m_Frame; }

    // True once a dispatch was refused (an internal error, logged): the frame's dispatches are
    // incomplete and GetComputeDispatches returns FAILURE instead of a partial list.
    bool Failed() const { return m_Failed; }

    // Dispatches added from now on belong to 'stage' (CLASSIFICATION or DENOISING, the default).
    void SetStage(DispatchStage stage) { m_Stage = stage; }

    // Fills the NRD_COMMON_CONSTANTS part of a pass's constant block.
    template <class Constants>
    void FillCommonConstants(Constants& c) const
    {
        c.gViewToWorld = m_Frame.viewToWorld;
        c.gWorldToClipPrev = m_Frame.worldToClipPrev;
        c.gWorldToViewPrev = m_Frame.worldToViewPrev;
        c.gViewToClip = m_Frame.viewToClip;
        c.gFrustum = m_Frame.frustum;
        const CommonSettings& s = m_Frame.common;
        c.gMotionVectorScale = {s.motionVectorScale[0], s.motionVectorScale[1], s.motionVectorScale[2],
                                s.isMotionVectorInWorldSpace ? 1.0f : 0.0f};
        c.gResourceSize = {m_Frame.width, m_Frame.height};
        c.gInvResourceSize = {1.0f / float(m_Frame.width), 1.0f / float(m_Frame.height)};
        c.gProjectY = m_Frame.projectY;
        c.gViewZSign = m_Frame.viewZSign;
        c.gDenoisingRange = s.denoisingRange;
        c.gDisocclusionThreshold = s.disocclusionThreshold;
        c.gFrameIndex = s.frameIndex;
        c.gResetHistory = m_Frame.resetHistory ? 1u : 0u;
        c.gCommonPad0 = 0;
        c.gCommonPad1 = 0;
    }

    // Adds a dispatch of template 'templateIndex' (as returned by MethodBuilder::AddDispatch)
    // covering 'threadsX' x 'threadsY' invocations.
    template <class Constants>
    void Dispatch(uint32_t templateIndex, const Constants& constants, uint32_t threadsX, uint32_t threadsY)
    {
        static_assert(sizeof(Constants) % 16 == 0 || sizeof(Constants) == 1, "std140 block size");
        PushDispatch(templateIndex, &constants, sizeof(Constants), threadsX, threadsY, nullptr);
    }

    template <class Constants>
    void DispatchIndirect(uint32_t templateIndex, const Constants& constants, uint32_t maxThreadsX, uint32_t maxThreadsY,
                          ResourceRef argumentsBuffer, uint32_t argumentsOffset)
    {
        IndirectArgs args = {argumentsBuffer, argumentsOffset};
        PushDispatch(templateIndex, &constants, sizeof(Constants), maxThreadsX, maxThreadsY, &args);
    }

private:
    struct IndirectArgs
    {
        ResourceRef buffer;
        uint32_t offset;
    };
    void PushDispatch(uint32_t templateIndex, const void* constants, uint32_t size, uint32_t threadsX, uint32_t threadsY,
                      const IndirectArgs* indirect);

    InstanceImpl& m_Instance;
    uint32_t m_MethodIndex;
    const FrameData& m_Frame;
    DispatchStage m_Stage = DispatchStage::DENOISING;
    bool m_Failed = false;
};

// Which settings struct a SetMethodSettings call carries.
enum class SettingsKind : uint32_t
{
    SIGMA,
    REFERENCE,
    TILED_SHADOW,
    REBLUR,
    CONFIDENCE,
    REFLECTION,
    RELAX,
};

class MethodBase
{
public:
    virtual ~MethodBase() = default;
    // Validates and stores settings; INVALID_ARGUMENT (with a message) leaves them unchanged.
    virtual Result SetSettings(SettingsKind kind, const void* settings, const Logger& log) = 0;
    // Adds this frame's dispatches.
    virtual void Update(FrameContext& context) = 0;
};

// What a method declares at creation: pool textures, buffers and dispatch templates.
class MethodBuilder
{
public:
    MethodBuilder(InstanceImpl& instance, uint32_t methodIndex) : m_Instance(instance), m_MethodIndex(methodIndex) {}

    ResourceRef AddPermanentTexture(Format format, uint16_t downsampleX = 1, uint16_t downsampleY = 1);
    ResourceRef AddTransientTexture(Format format, uint16_t downsampleX = 1, uint16_t downsampleY = 1);
    ResourceRef AddBuffer(const BufferDesc& desc);
    // Creation size (buffers sized per pixel or per tile).
    uint32_t RenderWidth() const;
    uint32_t RenderHeight() const;

    // Declares a dispatch of pass 'Pass' with its resources in binding order. Returns the template
    // index for FrameContext::Dispatch. A count or type mismatch with the pass declaration is a bug
    // in the method: it is reported and makes CreateDenoiser fail.
    template <class Pass>
    uint32_t AddDispatch(const char* name, std::initializer_list<ResourceRef> resources)
    {
        static_assert(BindingsAreSequential(Pass::kBindings), "bindings must be 0..N-1 in declaration order");
        return AddDispatchImpl(name, Pass::kName, Pass::kBindings, Pass::kBindingsNum, Pass::kHasConstants,
                               Pass::kHasConstants ? uint32_t(sizeof(typename Pass::Constants)) : 0u, Pass::kGroupX,
                               Pass::kGroupY, resources.begin(), uint32_t(resources.size()));
    }

private:
    uint32_t AddDispatchImpl(const char* name, const char* shaderName, const BindingDecl* bindings, uint32_t bindingsNum,
                             bool hasConstants, uint32_t constantsSize, uint16_t groupX, uint16_t groupY,
                             const ResourceRef* resources, uint32_t resourcesNum);

    InstanceImpl& m_Instance;
    uint32_t m_MethodIndex;
};

// HitDistanceParameters check shared by the methods that take them (Source/HitDistance.cpp): logs
// "SetMethodSettings: <owner>::<field> ..." and returns INVALID_ARGUMENT outside the documented ranges.
Result ValidateHitDistanceParameters(const HitDistanceParameters& parameters, const char* owner, const Logger& log);

// Factory of each method family (Source/<Family>.cpp).
std::unique_ptr<MethodBase> CreateSigma(MethodBuilder& builder, Method method);
std::unique_ptr<MethodBase> CreateTiledShadow(MethodBuilder& builder, Method method);
std::unique_ptr<MethodBase> CreateReference(MethodBuilder& builder, Method method);
std::unique_ptr<MethodBase> CreateReblur(MethodBuilder& builder, Method method);
std::unique_ptr<MethodBase> CreateConfidence(MethodBuilder& builder, Method method);
std::unique_ptr<MethodBase> CreateReflection(MethodBuilder& builder, Method method);
std::unique_ptr<MethodBase> CreateRelax(MethodBuilder& builder, Method method);

class InstanceImpl
{
public:
    explicit InstanceImpl(const DenoiserCreationDesc& desc);
    const AllocationCallbacks* Allocator() const { return m_Allocator; }

    Result Create(const DenoiserCreationDesc& desc);
    Result SetCommonSettings(const CommonSettings& settings);
    Result SetMethodSettings(Identifier identifier, SettingsKind kind, const void* settings);
    Result GetComputeDispatches(const Identifier* identifiers, uint32_t identifiersNum, DispatchStage stage,
                                const DispatchDesc*& outDispatches, uint32_t& outDispatchesNum);
    const DenoiserDesc& GetDesc() const { return m_Desc; }
    const Logger& Log() const { return m_Log; }

private:
    friend class MethodBuilder;
    friend class FrameContext;

    struct MethodData
    {
        explicit MethodData(const AllocationCallbacks* a)
            : templates(StdAllocator<uint32_t>(a)), transients(StdAllocator<TextureDesc>(a)),
              transientRemap(StdAllocator<uint16_t>(a)), dispatches(StdAllocator<DispatchDesc>(a)),
              constants(StdAllocator<uint8_t>(a)), constantOffsets(StdAllocator<uint32_t>(a)),
              stages(StdAllocator<DispatchStage>(a)) {}

        MethodDesc desc = {};
        std::unique_ptr<MethodBase> impl;
        Vector<uint32_t> templates;          // Into m_Templates, local index -> global.
        Vector<TextureDesc> transients;      // Local transient textures (before sharing).
        Vector<uint16_t> transientRemap;     // Local -> shared transient pool index.
        Vector<DispatchDesc> dispatches;     // This frame's part (pointers into below).
        Vector<uint8_t> constants;           // This frame's constant bytes.
        Vector<uint32_t> constantOffsets;    // Per dispatch, into 'constants'.
        Vector<DispatchStage> stages;        // Per dispatch.
        uint64_t updatedEpoch = 0;
    };

    uint16_t AddPipeline(const char* shaderName, const BindingDecl* bindings, uint32_t bindingsNum, bool hasConstants,
                         uint32_t constantsSize, uint16_t groupX, uint16_t groupY);
    void FinalizePools();
    bool UpdateMethod(uint32_t methodIndex); // False: an internal error, nothing recorded.

    AllocationCallbacks m_AllocationCallbacks = {};
    const AllocationCallbacks* m_Allocator = nullptr; // Null: operator new.
    Logger m_Log;
    DenoiserDesc m_Desc = {};
    Vector<MethodData> m_Methods;
    Vector<PipelineDesc> m_Pipelines;
    Vector<ResourceRangeDesc> m_Ranges; // All pipelines' ranges; m_PipelineRangeFirst indexes it.
    Vector<uint32_t> m_PipelineRangeFirst;
    Vector<TextureDesc> m_PermanentPool;
    Vector<TextureDesc> m_TransientPool;
    Vector<BufferDesc> m_Buffers;
    Vector<Sampler> m_Samplers;
    Vector<DispatchTemplate> m_Templates;
    Vector<ResourceDesc> m_Resources;
    Vector<DispatchDesc> m_Output;
    FrameData m_Frame = {};
    uint64_t m_Epoch = 0; // Incremented by every successful SetCommonSettings.
    uint32_t m_PrevWidth = 0, m_PrevHeight = 0;
    bool m_HasPrevFrame = false;
    bool m_BuildFailed = false;
};

} // namespace nrd
