// REFLECTION: glossy reflection denoiser with variable-rate tracing, FidelityFX-style (document 000,
// "Reflection denoiser", and document 002, its pass-by-pass description).
//
// CLASSIFICATION stage: per-pixel decision (needs the denoiser / traces a ray / receives a quad
// neighbour's copy; 1, 2 or 4 rays per 2x2 quad, more where the temporal variance is high), ray list
// by local prefix sum + ray counter, tile list of the 8x8 tiles that need the denoiser, indirect
// arguments. The application then traces the listed rays. DENOISING stage, over the listed tiles
// only (indirect dispatches): reprojection, spatial, temporal and blur passes.
//
// Resources: permanent history RGBA16F (radiance + sample count), temporal variance R16F, two
// (ping-pong) viewZ R32F and normal + roughness RGBA16F; transient reprojected, spatial and
// temporal RGBA16F and the 8x8 tile average (RGBA16F) at 1/8 x 1/8; pool buffers: ray list (4 bytes
// per pixel), tile list (4 bytes per tile), counters + indirect args.
#include "InstanceImpl.h"

#include "../Shaders/Reflection/Reflection_Constants.h"

namespace nrd
{
namespace passes
{
NRD_PASS_TYPES
#include "../Shaders/Reflection/Reflection_Classify.resources.h"
#include "../Shaders/Reflection/Reflection_PrepareArgs.resources.h"
#include "../Shaders/Reflection/Reflection_Reproject.resources.h"
#include "../Shaders/Reflection/Reflection_Spatial.resources.h"
#include "../Shaders/Reflection/Reflection_Temporal.resources.h"
#include "../Shaders/Reflection/Reflection_Blur.resources.h"
} // namespace passes

namespace
{

static_assert(sizeof(passes::Reflection_Reproject::Constants) == sizeof(passes::Reflection_Spatial::Constants) &&
                  sizeof(passes::Reflection_Reproject::Constants) == sizeof(passes::Reflection_Temporal::Constants) &&
                  sizeof(passes::Reflection_Reproject::Constants) == sizeof(passes::Reflection_Blur::Constants),
              "the denoising passes share one constant layout");

constexpr uint32_t kDenoiseArgsOffset = 4 * sizeof(uint32_t); // BufferContent::RAY_COUNTERS words 4..6.

class Reflection final : public MethodBase
{
public:
    explicit Reflection(MethodBuilder& builder)
    {
        const uint32_t w = builder.RenderWidth(), h = builder.RenderHeight();
        ResourceRef history = builder.AddPermanentTexture(Format::RGBA16_SFLOAT);
        ResourceRef variance = builder.AddPermanentTexture(Format::R16_SFLOAT);
        ResourceRef viewZHistory[2] = {builder.AddPermanentTexture(Format::R32_SFLOAT),
                                       builder.AddPermanentTexture(Format::R32_SFLOAT)};
        ResourceRef normalHistory[2] = {builder.AddPermanentTexture(Format::RGBA16_SFLOAT),
                                        builder.AddPermanentTexture(Format::RGBA16_SFLOAT)};
        ResourceRef reprojected = builder.AddTransientTexture(Format::RGBA16_SFLOAT);
        ResourceRef spatial = builder.AddTransientTexture(Format::RGBA16_SFLOAT);
        ResourceRef temporal = builder.AddTransientTexture(Format::RGBA16_SFLOAT);
        ResourceRef tileAverage = builder.AddTransientTexture(Format::RGBA16_SFLOAT, REFLECTION_TILE_SIZE, REFLECTION_TILE_SIZE);

        BufferDesc rayList;
        rayList.size = uint64_t(w) * h * sizeof(uint32_t);
        rayList.content = BufferContent::RAY_LIST;
        BufferDesc tileList;
        tileList.size = uint64_t(DivideUp(w, REFLECTION_TILE_SIZE)) * DivideUp(h, REFLECTION_TILE_SIZE) * sizeof(uint32_t);
        // The live counters are reset by the arguments pass of each frame: zero at creation.
        BufferDesc counters;
        counters.size = REFLECTION_COUNTERS_WORDS * sizeof(uint32_t);
        counters.isIndirectArguments = true;
        counters.isPermanent = true;
        counters.content = BufferContent::RAY_COUNTERS;
        m_RayList = builder.AddBuffer(rayList);
        ResourceRef tiles = builder.AddBuffer(tileList);
        m_Counters = builder.AddBuffer(counters);

        ResourceRef viewZ = App(ResourceType::IN_VIEWZ), normal = App(ResourceType::IN_NORMAL_ROUGHNESS);
        ResourceRef mv = App(ResourceType::IN_MV), in = App(ResourceType::IN_SPEC_RADIANCE_HITDIST);
        ResourceRef out = App(ResourceType::OUT_SPEC_RADIANCE_HITDIST);

        // History of depth, normal and roughness alternates between two textures by frame parity.
        for (uint32_t parity = 0; parity < 2; parity++)
        {
            m_Classify[parity] = builder.AddDispatch<passes::Reflection_Classify>(
                "REFLECTION - Classify", {normal, viewZ, variance, viewZHistory[parity], normalHistory[parity],
                                          m_RayList, tiles, m_Counters});
            m_Reproject[parity] = builder.AddDispatch<passes::Reflection_Reproject>(
                "REFLECTION - Reproject", {in, normal, viewZ, mv, viewZHistory[1 - parity], normalHistory[1 - parity],
                                           history, tiles, reprojected, tileAverage, out});
        }
        m_PrepareArgs = builder.AddDispatch<passes::Reflection_PrepareArgs>("REFLECTION - Prepare arguments", {m_Counters});
        m_Spatial = builder.AddDispatch<passes::Reflection_Spatial>("REFLECTION - Spatial",
                                                                    {in, normal, viewZ, tileAverage, tiles, spatial});
        m_Temporal = builder.AddDispatch<passes::Reflection_Temporal>(
            "REFLECTION - Temporal", {spatial, reprojected, normal, viewZ, tiles, history, variance, temporal, out});
        m_Blur = builder.AddDispatch<passes::Reflection_Blur>("REFLECTION - Blur", {temporal, normal, viewZ, tiles, out});
    }

    Result SetSettings(SettingsKind kind, const void* settings, const Logger& log) override
    {
        if (kind != SettingsKind::REFLECTION)
        {
            log.Error("SetMethodSettings: REFLECTION takes ReflectionSettings");
            return Result::INVALID_ARGUMENT;
        }
        const ReflectionSettings& s = *static_cast<const ReflectionSettings*>(settings);
        if (ValidateHitDistanceParameters(s.hitDistanceParameters, "ReflectionSettings::hitDistanceParameters", log) !=
            Result::SUCCESS)
            return Result::INVALID_ARGUMENT;
        const char* error = nullptr;
        if (!(s.roughnessThreshold >= 0.0f && s.roughnessThreshold <= 1.0f))
            error = "roughnessThreshold is outside [0, 1]";
        else if (!(s.mirrorRoughness >= 0.0f && s.mirrorRoughness <= 1.0f))
            error = "mirrorRoughness is outside [0, 1]";
        else if (s.raysPerQuad != 1 && s.raysPerQuad != 2 && s.raysPerQuad != 4)
            error = "raysPerQuad is not 1, 2 or 4";
        else if (!(s.temporalVarianceThreshold > 0.0f && s.temporalVarianceThreshold <= 1.0f))
            error = "temporalVarianceThreshold is outside (0, 1]";
        else if (s.maxHistoryFrameNum < 1 || s.maxHistoryFrameNum > REFLECTION_MAX_HISTORY_FRAME_NUM)
            error = "maxHistoryFrameNum is outside [1, 63]";
        else if (!(s.hitReprojectionRoughness >= 0.0f && s.hitReprojectionRoughness <= 1.0f))
            error = "hitReprojectionRoughness is outside [0, 1]";
        else if (!(s.historyClipSigma >= 0.25f && s.historyClipSigma <= 16.0f))
            error = "historyClipSigma is outside [0.25, 16]";
        else if (!(s.historyClipLeeway >= 0.0f && s.historyClipLeeway <= 4.0f))
            error = "historyClipLeeway is outside [0, 4]";
        else if (!(s.normalSigma >= 0.0f && s.normalSigma <= 4096.0f))
            error = "normalSigma is outside [0, 4096]";
        else if (!(s.depthSigma > 0.0f && s.depthSigma <= 64.0f))
            error = "depthSigma is outside (0, 64]";
        if (error)
        {
            log.Error("SetMethodSettings: ReflectionSettings::%s", error);
            return Result::INVALID_ARGUMENT;
        }
        m_Settings = s;
        return Result::SUCCESS;
    }

    void Update(FrameContext& context) override
    {
        const FrameData& frame = context.Frame();
        const ReflectionSettings& s = m_Settings;
        const uint32_t parity = m_MethodFrame & 1u;
        m_MethodFrame++;
        const bool isHistoryValid = !frame.resetHistory && frame.isClipToClipPrevValid;

        context.SetStage(DispatchStage::CLASSIFICATION);
        {
            passes::Reflection_Classify::Constants c = {};
            context.FillCommonConstants(c);
            c.gMirrorRoughness = s.mirrorRoughness;
            c.gRoughnessThreshold = s.roughnessThreshold;
            c.gTemporalVarianceThreshold = s.temporalVarianceThreshold;
            c.gRaysPerQuad = s.raysPerQuad;
            c.gFlags = (s.enableTemporalVarianceGuidedTracing ? REFLECTION_FLAG_GUIDED_TRACING : 0u) |
                       (isHistoryValid ? REFLECTION_FLAG_HISTORY_VALID : 0u);
            context.Dispatch(m_Classify[parity], c, frame.width, frame.height);
            passes::Reflection_PrepareArgs::Constants none;
            context.Dispatch(m_PrepareArgs, none, 1, 1);
        }

        context.SetStage(DispatchStage::DENOISING);
        passes::Reflection_Reproject::Constants d = {};
        context.FillCommonConstants(d);
        const HitDistanceParameters& hd = s.hitDistanceParameters;
        d.gHitDistParams = {hd.A, hd.B, hd.C, hd.D};
        d.gMirrorRoughness = s.mirrorRoughness;
        d.gRoughnessThreshold = s.roughnessThreshold;
        d.gHitReprojectionRoughness = s.hitReprojectionRoughness;
        d.gMaxHistoryFrameNum = float(s.maxHistoryFrameNum);
        d.gHistoryClipSigma = s.historyClipSigma;
        d.gHistoryClipLeeway = s.historyClipLeeway;
        d.gNormalSigma = s.normalSigma;
        d.gDepthSigma = s.depthSigma;
        d.gFlags = (isHistoryValid ? REFLECTION_FLAG_HISTORY_VALID : 0u) | (s.enableSpatial ? REFLECTION_FLAG_SPATIAL : 0u) |
                   (s.enableBlur ? REFLECTION_FLAG_BLUR : 0u);
        // Upper bound of the indirect grids: every tile.
        const uint32_t tiles = DivideUp(frame.width, REFLECTION_TILE_SIZE) * DivideUp(frame.height, REFLECTION_TILE_SIZE);
        const uint32_t threads = tiles * REFLECTION_TILE_SIZE;
        context.DispatchIndirect(m_Reproject[parity], d, threads, REFLECTION_TILE_SIZE, m_Counters, kDenoiseArgsOffset);
        context.DispatchIndirect(m_Spatial, d, threads, REFLECTION_TILE_SIZE, m_Counters, kDenoiseArgsOffset);
        context.DispatchIndirect(m_Temporal, d, threads, REFLECTION_TILE_SIZE, m_Counters, kDenoiseArgsOffset);
        if (s.enableBlur)
            context.DispatchIndirect(m_Blur, d, threads, REFLECTION_TILE_SIZE, m_Counters, kDenoiseArgsOffset);
    }

private:
    ReflectionSettings m_Settings = {};
    ResourceRef m_RayList, m_Counters;
    uint32_t m_Classify[2] = {};
    uint32_t m_Reproject[2] = {};
    uint32_t m_PrepareArgs = 0, m_Spatial = 0, m_Temporal = 0, m_Blur = 0;
    uint32_t m_MethodFrame = 0;
};

} // namespace

std::unique_ptr<MethodBase> CreateReflection(MethodBuilder& builder, Method)
{
    return std::unique_ptr<MethodBase>(new Reflection(builder));
}

} // namespace nrd
