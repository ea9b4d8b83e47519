// TILED_SHADOW: tile-classified shadow denoiser for one ray per pixel (document 000, "Shadow
// denoiser"): prepare (8x4-pixel bitmasks), tile classification (local moments from the bitmasks,
// disocclusion, reprojection, history clamp and blend), then edge-avoiding a-trous passes
// (Dammertz et al. 2010, "Edge-Avoiding A-Trous Wavelet Transform for fast Global Illumination
// Filtering") with steps 1, 2 and 4. Tiles without spatial variance are skipped.
//
// Resources: permanent state RG32_UINT (viewZ + packed history, 8 bytes per pixel) and a 32-byte
// counter buffer; transient two RG16F (shadow and variance, ping-pong), R32_UINT (packed temporal
// moments) and two R32_UINT textures at 1/8 x 1/4 resolution (bitmasks, tile classes).
#include "InstanceImpl.h"
#include "ShadowLightMotion.h"

#include <cmath>
#include <cstdlib>

namespace nrd
{
namespace passes
{
NRD_PASS_TYPES
#include "../Shaders/TiledShadow/TiledShadow_Prepare.resources.h"
#include "../Shaders/TiledShadow/TiledShadow_Classify.resources.h"
#define TS_SHADOW_DATA 1
#include "../Shaders/TiledShadow/TiledShadow_Classify.resources.h"
#undef TS_SHADOW_DATA
#define TILED_SHADOW_STEP 1
#include "../Shaders/TiledShadow/TiledShadow_Filter.resources.h"
#undef TILED_SHADOW_STEP
#define TILED_SHADOW_STEP 2
#include "../Shaders/TiledShadow/TiledShadow_Filter.resources.h"
#undef TILED_SHADOW_STEP
#define TILED_SHADOW_STEP 4
#include "../Shaders/TiledShadow/TiledShadow_Filter.resources.h"
#undef TILED_SHADOW_STEP
} // namespace passes

namespace
{

// Mirrors of TiledShadow_Common.glsl.
constexpr uint32_t kFlagTileSkipping = 1;
constexpr uint32_t kFlagHistoryValid = 2;
constexpr uint32_t kCountersBytes = 2 * TILED_SHADOW_COUNTERS_SLOT_SIZE * sizeof(uint32_t);

static_assert(uint32_t(TiledShadowDebug::MAX_NUM) == 5, "TS_DEBUG_* in TiledShadow_Common.glsl");
static_assert(TILED_SHADOW_MAX_HISTORY_FRAME_NUM == 63, "TS_MAX_HISTORY in TiledShadow_Common.glsl (8-bit count * 4)");
static_assert(TILED_SHADOW_MAX_NEIGHBORHOOD_RADIUS == 8, "RADIUS_MAX in TiledShadow_Classify.comp");
static_assert(sizeof(passes::TiledShadow_Classify::Constants) == sizeof(passes::TiledShadow_ClassifyShadowData::Constants),
              "the classification's variants share one constant block");

class TiledShadow final : public MethodBase
{
public:
    explicit TiledShadow(MethodBuilder& builder)
    {
        ResourceRef mask = builder.AddTransientTexture(Format::R32_UINT, 8, 4);
        ResourceRef tileClass = builder.AddTransientTexture(Format::R32_UINT, 8, 4);
        ResourceRef shadowA = builder.AddTransientTexture(Format::RG16_SFLOAT);
        ResourceRef shadowB = builder.AddTransientTexture(Format::RG16_SFLOAT);
        ResourceRef moments = builder.AddTransientTexture(Format::R32_UINT);
        ResourceRef state = builder.AddPermanentTexture(Format::RG32_UINT);
        m_InvStateSize = {1.0f / float(builder.RenderWidth()), 1.0f / float(builder.RenderHeight())};
        BufferDesc countersDesc;
        countersDesc.size = kCountersBytes;
        countersDesc.isPermanent = true;
        ResourceRef counters = builder.AddBuffer(countersDesc);

        ResourceRef viewZ = App(ResourceType::IN_VIEWZ), normal = App(ResourceType::IN_NORMAL_ROUGHNESS);
        ResourceRef mv = App(ResourceType::IN_MV), out = App(ResourceType::OUT_SHADOW_TRANSLUCENCY);

        m_Prepare = builder.AddDispatch<passes::TiledShadow_Prepare>(
            "TILED_SHADOW - Prepare", {App(ResourceType::IN_SHADOW_VISIBILITY), App(ResourceType::IN_VIEWZ), mask});
        // The same pass over the prepared masks or the application's (isBitmaskInput).
        m_Classify[0] = builder.AddDispatch<passes::TiledShadow_Classify>(
            "TILED_SHADOW - Classify", {mask, viewZ, normal, mv, state, shadowA, moments, tileClass, out, counters});
        m_Classify[1] = builder.AddDispatch<passes::TiledShadow_Classify>(
            "TILED_SHADOW - Classify", {App(ResourceType::IN_SHADOW_BITMASK), viewZ, normal, mv, state, shadowA, moments,
                                        tileClass, out, counters});
        // With IN_SHADOWDATA (isShadowDataInput): the same two, and the light's move.
        m_Classify[2] = builder.AddDispatch<passes::TiledShadow_ClassifyShadowData>(
            "TILED_SHADOW - Classify", {mask, viewZ, normal, mv, state, shadowA, moments, tileClass, out, counters,
                                        App(ResourceType::IN_SHADOWDATA)});
        m_Classify[3] = builder.AddDispatch<passes::TiledShadow_ClassifyShadowData>(
            "TILED_SHADOW - Classify", {App(ResourceType::IN_SHADOW_BITMASK), viewZ, normal, mv, state, shadowA, moments,
                                        tileClass, out, counters, App(ResourceType::IN_SHADOWDATA)});
        // Ping-pong between two RG16F textures; the last pass run writes OUT.
        m_Filter[0] = builder.AddDispatch<passes::TiledShadow_Filter1>(
            "TILED_SHADOW - A-trous step 1", {shadowA, moments, viewZ, normal, tileClass, shadowB, out, state});
        m_Filter[1] = builder.AddDispatch<passes::TiledShadow_Filter2>(
            "TILED_SHADOW - A-trous step 2", {shadowB, moments, viewZ, normal, tileClass, shadowA, out, state});
        m_Filter[2] = builder.AddDispatch<passes::TiledShadow_Filter4>(
            "TILED_SHADOW - A-trous step 4", {shadowA, moments, viewZ, normal, tileClass, shadowB, out, state});
    }

    Result SetSettings(SettingsKind kind, const void* settings, const Logger& log) override
    {
        if (kind != SettingsKind::TILED_SHADOW)
        {
            log.Error("SetMethodSettings: TILED_SHADOW takes TiledShadowSettings");
            return Result::INVALID_ARGUMENT;
        }
        const TiledShadowSettings& s = *static_cast<const TiledShadowSettings*>(settings);
        const char* error = nullptr;
        if (s.neighborhoodRadius < 1 || s.neighborhoodRadius > TILED_SHADOW_MAX_NEIGHBORHOOD_RADIUS)
            error = "neighborhoodRadius is outside [1, 8]";
        else if (!(s.historyClampSigma > 0.0f && s.historyClampSigma <= 8.0f))
            error = "historyClampSigma is outside (0, 8]";
        else if (!(s.disocclusionThresholdGrazing > 0.0f && s.disocclusionThresholdGrazing <= 1.0f))
            error = "disocclusionThresholdGrazing is outside (0, 1]";
        else if (!(s.planeDistanceSensitivity > 0.0f && s.planeDistanceSensitivity <= 1.0f))
            error = "planeDistanceSensitivity is outside (0, 1]";
        else if (!(s.normalPower >= 0.0f && s.normalPower <= 128.0f))
            error = "normalPower is outside [0, 128]";
        else if (s.atrousPassNum < 1 || s.atrousPassNum > 3)
            error = "atrousPassNum is outside [1, 3]";
        else if (s.maxHistoryFrameNum < 1 || s.maxHistoryFrameNum > TILED_SHADOW_MAX_HISTORY_FRAME_NUM)
            error = "maxHistoryFrameNum is outside [1, 63]";
        else if (uint32_t(s.debugView) >= uint32_t(TiledShadowDebug::MAX_NUM))
            error = "debugView is unknown";
        else
        {
            for (int i = 0; i < 3 && !error; i++)
                if (!std::isfinite(s.lightDirection[i]))
                    error = "lightDirection is not finite";
        }
        if (error)
        {
            log.Error("SetMethodSettings: TiledShadowSettings::%s", error);
            return Result::INVALID_ARGUMENT;
        }
        Result lightResult = ValidateShadowLight("TiledShadowSettings", s.tanOfLightAngularRadius, s.lightPosition, s.lightRadius, log);
        if (lightResult != Result::SUCCESS)
            return lightResult;
        m_Settings = s;
        return Result::SUCCESS;
    }

    void Update(FrameContext& context) override
    {
        const FrameData& frame = context.Frame();
        const TiledShadowSettings& s = m_Settings;
        m_MethodFrame++;

        if (!s.isBitmaskInput)
        {
            passes::TiledShadow_Prepare::Constants c = {};
            context.FillCommonConstants(c);
            context.Dispatch(m_Prepare, c, DivideUp(frame.width, 8), DivideUp(frame.height, 4));
        }

        passes::TiledShadow_Classify::Constants c = {};
        context.FillCommonConstants(c);
        c.gClipToClipPrev = frame.clipToClipPrev;
        float weights[12] = {}, steps[12] = {};
        const float radius = float(s.neighborhoodRadius);
        for (uint32_t i = 0; i <= s.neighborhoodRadius; i++)
            weights[i] = std::exp(-3.0f * float(i * i) / ((radius + 1.0f) * (radius + 1.0f)));
        for (uint32_t i = 0; i < 9; i++)
            steps[i] = weights[i] - weights[i + 1];
        c.gMomentWeights0 = {weights[0], weights[1], weights[2], weights[3]};
        c.gMomentWeights1 = {weights[4], weights[5], weights[6], weights[7]};
        c.gMomentWeights2 = {weights[8], 0.0f, 0.0f, 0.0f};
        c.gMomentSteps0 = {steps[0], steps[1], steps[2], steps[3]};
        c.gMomentSteps1 = {steps[4], steps[5], steps[6], steps[7]};
        c.gMomentSteps2 = {steps[8], 0.0f, 0.0f, 0.0f};
        float weightSum = 0.0f, weightSquaredSum = 0.0f;
        for (int i = -int(s.neighborhoodRadius); i <= int(s.neighborhoodRadius); i++)
        {
            weightSum += weights[std::abs(i)];
            weightSquaredSum += weights[std::abs(i)] * weights[std::abs(i)];
        }
        c.gLocalMeanNoise = weightSquaredSum / (weightSum * weightSum); // sqrt(sum w^2) / sum w of the 2D kernel.
        c.gMomentWeights2.y = weightSum * weightSum;                       // Weight of a window inside the image.
        c.gHistoryClampSigma = s.historyClampSigma;
        c.gDisocclusionThresholdGrazing =
            s.disocclusionThresholdGrazing > frame.common.disocclusionThreshold ? s.disocclusionThresholdGrazing
                                                                                : frame.common.disocclusionThreshold;
        c.gMaxHistoryFrameNum = float(s.maxHistoryFrameNum);
        c.gFlags = (s.enableTileSkipping ? kFlagTileSkipping : 0u) |
                   (!frame.resetHistory && frame.isClipToClipPrevValid ? kFlagHistoryValid : 0u);
        c.gDebugView = uint32_t(s.debugView);
        c.gCounterSlot = m_MethodFrame & 1u;
        c.gMethodFrame = m_MethodFrame;
        c.gInvStateSize = m_InvStateSize;
        if (s.isShadowDataInput)
        {
            SetShadowLightMotion(m_LightMotion, s, frame, c);
        }
        context.Dispatch(m_Classify[(s.isShadowDataInput ? 2 : 0) + (s.isBitmaskInput ? 1 : 0)], c, frame.width, frame.height);

        // A debug view keeps the first pass, which stores the history (so that the views show what
        // a running denoiser sees), without letting it write OUT_SHADOW_TRANSLUCENCY.
        const bool isDebug = s.debugView != TiledShadowDebug::NONE;
        for (uint32_t pass = 0; pass < (isDebug ? 1u : s.atrousPassNum); pass++)
        {
            // All three passes share one constant layout.
            passes::TiledShadow_Filter1::Constants f = {};
            context.FillCommonConstants(f);
            f.gPlaneDistanceScale = 1.44269504f / s.planeDistanceSensitivity;
            f.gNormalPower = s.normalPower;
            f.gIsFirstPass = pass == 0 ? 1u : 0u;
            f.gIsLastPass = !isDebug && pass + 1 == s.atrousPassNum ? 1u : 0u;
            context.Dispatch(m_Filter[pass], f, frame.width, frame.height);
        }
    }

private:
    TiledShadowSettings m_Settings = {};
    uint32_t m_Prepare = 0;
    // Mask from the prepare pass / the application's, then the same with IN_SHADOWDATA.
    uint32_t m_Classify[4] = {};
    ShadowLightMotion m_LightMotion;
    uint32_t m_Filter[3] = {};
    uint32_t m_MethodFrame = 0;
    glsl::vec2 m_InvStateSize = {}; // The permanent state's texel size in uv (the render size's).
};

static_assert(sizeof(passes::TiledShadow_Filter1::Constants) == sizeof(passes::TiledShadow_Filter2::Constants) &&
                  sizeof(passes::TiledShadow_Filter1::Constants) == sizeof(passes::TiledShadow_Filter4::Constants),
              "the a-trous passes share one constant layout");

} // namespace

std::unique_ptr<MethodBase> CreateTiledShadow(MethodBuilder& builder, Method)
{
    return std::unique_ptr<MethodBase>(new TiledShadow(builder));
}

} // namespace nrd
