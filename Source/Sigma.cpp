// SIGMA: penumbra-driven shadow denoiser, SIGMA_SHADOW and SIGMA_SHADOW_TRANSLUCENCY (document 004).
//
// Per frame, for a W x H input:
//   1. Classify tiles      16x16 tiles: uniform (copy), mixed (denoise) or sky (skip), plus the
//                          largest kernel radius.
//      Smooth tiles        one thread per tile: the map dilated by that reach, the per-tile mode
//                          (sky / copy / denoise) the next passes read.
//   2. Blur                penumbra estimate (dense 5x5 of occluded neighbours), dense 5x5 + 8-tap
//                          rotated disk on the tangent plane, radius from the penumbra.
//   3. Post-blur           half radius, independently rotated, 3x3 + 8 taps.
//   4. Temporal stabilization  reprojection, disocclusion test, neighbourhood clamp, anti-lag,
//                          up to maxStabilizedFrameNum frames; skipped (post-blur writes the output)
//                          when maxStabilizedFrameNum is 0. History ping-pongs by frame parity.
#include "InstanceImpl.h"
#include "ShadowLightMotion.h"

#include <algorithm>
#include <cmath>
#include <type_traits>

namespace nrd
{
namespace passes
{
NRD_PASS_TYPES
#undef SIGMA_TRANSLUCENCY
#define SIGMA_TRANSLUCENCY 0
#include "../Shaders/Sigma/Sigma_ClassifyTiles.resources.h"
#include "../Shaders/Sigma/Sigma_Blur.resources.h"
#include "../Shaders/Sigma/Sigma_PostBlur.resources.h"
#include "../Shaders/Sigma/Sigma_TemporalStabilization.resources.h"
#undef SIGMA_TRANSLUCENCY
#define SIGMA_TRANSLUCENCY 1
#include "../Shaders/Sigma/Sigma_ClassifyTiles.resources.h"
#include "../Shaders/Sigma/Sigma_Blur.resources.h"
#include "../Shaders/Sigma/Sigma_PostBlur.resources.h"
#include "../Shaders/Sigma/Sigma_TemporalStabilization.resources.h"
#undef SIGMA_TRANSLUCENCY
#include "../Shaders/Sigma/Sigma_SmoothTiles.resources.h" // One pipeline for both methods.
} // namespace passes

namespace
{

// Kernel radius per pixel of penumbra radius at blurRadiusScale 1. A penumbra of radius r is a
// ramp 2r wide; a kernel as wide as the ramp would bias its dark end (where relative errors are
// largest) and flatten the ramp, so the kernel covers about half of it and temporal
// stabilization removes the remaining noise.
constexpr float kKernelRadiusPerPenumbraRadius = 0.6f;

struct ShadowPasses
{
    typedef passes::Sigma_Shadow_ClassifyTiles ClassifyTiles;
    typedef passes::Sigma_Shadow_Blur Blur;
    typedef passes::Sigma_Shadow_PostBlur PostBlur;
    typedef passes::Sigma_Shadow_TemporalStabilization TemporalStabilization;
    static constexpr Format kSignalFormat = Format::R16_SFLOAT;
    static constexpr const char* kClassifyName = "SIGMA_SHADOW - Classify tiles";
    static constexpr const char* kSmoothName = "SIGMA_SHADOW - Smooth tiles";
    static constexpr const char* kBlurName = "SIGMA_SHADOW - Blur";
    static constexpr const char* kPostBlurName = "SIGMA_SHADOW - Post-blur";
    static constexpr const char* kTemporalName = "SIGMA_SHADOW - Temporal stabilization";
};

struct ShadowTranslucencyPasses
{
    typedef passes::Sigma_ShadowTranslucency_ClassifyTiles ClassifyTiles;
    typedef passes::Sigma_ShadowTranslucency_Blur Blur;
    typedef passes::Sigma_ShadowTranslucency_PostBlur PostBlur;
    typedef passes::Sigma_ShadowTranslucency_TemporalStabilization TemporalStabilization;
    static constexpr Format kSignalFormat = Format::RGBA16_SFLOAT;
    static constexpr const char* kClassifyName = "SIGMA_SHADOW_TRANSLUCENCY - Classify tiles";
    static constexpr const char* kSmoothName = "SIGMA_SHADOW_TRANSLUCENCY - Smooth tiles";
    static constexpr const char* kBlurName = "SIGMA_SHADOW_TRANSLUCENCY - Blur";
    static constexpr const char* kPostBlurName = "SIGMA_SHADOW_TRANSLUCENCY - Post-blur";
    static constexpr const char* kTemporalName = "SIGMA_SHADOW_TRANSLUCENCY - Temporal stabilization";
};

// The four passes share one constant block layout (common + SIGMA_CONSTANTS).
static_assert(sizeof(ShadowPasses::ClassifyTiles::Constants) == sizeof(ShadowPasses::Blur::Constants) &&
                  sizeof(ShadowPasses::Blur::Constants) == sizeof(ShadowPasses::TemporalStabilization::Constants) &&
                  sizeof(ShadowPasses::Blur::Constants) ==
                      sizeof(ShadowTranslucencyPasses::TemporalStabilization::Constants),
              "SIGMA passes share one constant block");
static_assert(sizeof(ShadowPasses::Blur::Constants) % 16 == 0, "std140 block size");

Result ValidateSigmaSettings(const SigmaSettings& s, const Logger& log)
{
    for (int i = 0; i < 3; i++)
    {
        if (!std::isfinite(s.lightDirection[i]))
        {
            log.Error("SetMethodSettings: SigmaSettings::lightDirection[%d] is not finite", i);
            return Result::INVALID_ARGUMENT;
        }
    }
    Result lightResult = ValidateShadowLight("SigmaSettings", s.tanOfLightAngularRadius, s.lightPosition, s.lightRadius, log);
    if (lightResult != Result::SUCCESS)
        return lightResult;
    if (!(s.planeDistanceSensitivity > 0.0f && s.planeDistanceSensitivity <= 1.0f))
    {
        log.Error("SetMethodSettings: SigmaSettings::planeDistanceSensitivity %g is outside (0, 1]",
                  double(s.planeDistanceSensitivity));
        return Result::INVALID_ARGUMENT;
    }
    if (!(s.blurRadiusScale >= 0.0f && s.blurRadiusScale <= SIGMA_MAX_BLUR_RADIUS_SCALE))
    {
        log.Error("SetMethodSettings: SigmaSettings::blurRadiusScale %g is outside [0, %g]", double(s.blurRadiusScale),
                  double(SIGMA_MAX_BLUR_RADIUS_SCALE));
        return Result::INVALID_ARGUMENT;
    }
    if (s.maxStabilizedFrameNum > SIGMA_MAX_HISTORY_FRAME_NUM)
    {
        log.Error("SetMethodSettings: SigmaSettings::maxStabilizedFrameNum %u is outside [0, %u]",
                  s.maxStabilizedFrameNum, SIGMA_MAX_HISTORY_FRAME_NUM);
        return Result::INVALID_ARGUMENT;
    }
    return Result::SUCCESS;
}

template <class P> class Sigma final : public MethodBase
{
public:
    explicit Sigma(MethodBuilder& builder)
    {
        const ResourceRef normal = App(ResourceType::IN_NORMAL_ROUGHNESS);
        const ResourceRef viewZ = App(ResourceType::IN_VIEWZ);
        const ResourceRef mv = App(ResourceType::IN_MV);
        const ResourceRef shadowData = App(ResourceType::IN_SHADOWDATA);
        const ResourceRef output = App(ResourceType::OUT_SHADOW_TRANSLUCENCY);

        ResourceRef history[2], historyViewZ[2];
        for (int i = 0; i < 2; i++)
        {
            history[i] = builder.AddPermanentTexture(P::kSignalFormat);
            historyViewZ[i] = builder.AddPermanentTexture(Format::R32_UINT); // viewZ bits | history length
        }
        const ResourceRef tiles = builder.AddTransientTexture(Format::RG16_SFLOAT, 16, 16);
        const ResourceRef tileModes = builder.AddTransientTexture(Format::R8_UNORM, 16, 16);
        const ResourceRef penumbra = builder.AddTransientTexture(Format::R16_SFLOAT);
        const ResourceRef blurred = builder.AddTransientTexture(P::kSignalFormat);
        const ResourceRef postBlurred = builder.AddTransientTexture(P::kSignalFormat);

        if constexpr (std::is_same<P, ShadowTranslucencyPasses>::value)
        {
            const ResourceRef translucency = App(ResourceType::IN_SHADOW_TRANSLUCENCY);
            m_Classify = builder.AddDispatch<typename P::ClassifyTiles>(P::kClassifyName,
                                                                        {viewZ, shadowData, translucency, tiles});
            m_Blur = builder.AddDispatch<typename P::Blur>(
                P::kBlurName, {normal, viewZ, shadowData, tileModes, translucency, blurred, penumbra});
        }
        else
        {
            m_Classify = builder.AddDispatch<typename P::ClassifyTiles>(P::kClassifyName, {viewZ, shadowData, tiles});
            m_Blur = builder.AddDispatch<typename P::Blur>(P::kBlurName,
                                                           {normal, viewZ, shadowData, tileModes, blurred, penumbra});
        }
        m_Smooth = builder.AddDispatch<passes::Sigma_SmoothTiles>(P::kSmoothName, {tiles, tileModes});
        m_PostBlur = builder.AddDispatch<typename P::PostBlur>(
            P::kPostBlurName, {normal, viewZ, blurred, penumbra, tileModes, postBlurred});
        m_PostBlurToOutput = builder.AddDispatch<typename P::PostBlur>(
            P::kPostBlurName, {normal, viewZ, blurred, penumbra, tileModes, output});
        for (int i = 0; i < 2; i++)
        {
            // Frame parity i reads history[1 - i] and writes history[i].
            m_Temporal[i] = builder.AddDispatch<typename P::TemporalStabilization>(
                P::kTemporalName, {normal, viewZ, mv, postBlurred, penumbra, tileModes, history[1 - i],
                                   historyViewZ[1 - i], output, history[i], historyViewZ[i]});
        }
    }

    Result SetSettings(SettingsKind kind, const void* settings, const Logger& log) override
    {
        if (kind != SettingsKind::SIGMA)
        {
            log.Error("SetMethodSettings: SIGMA_* methods take SigmaSettings");
            return Result::INVALID_ARGUMENT;
        }
        const SigmaSettings& s = *static_cast<const SigmaSettings*>(settings);
        Result result = ValidateSigmaSettings(s, log);
        if (result == Result::SUCCESS)
            m_Settings = s;
        return result;
    }

    void Update(FrameContext& context) override
    {
        const FrameData& frame = context.Frame();
        const bool isStabilized = m_Settings.maxStabilizedFrameNum != 0;

        typename P::Blur::Constants c = {};
        context.FillCommonConstants(c);
        // History written while stabilization was off is stale.
        if (isStabilized && !m_WasStabilized)
            c.gResetHistory = 1u;
        c.gLightDirectionView = DirectionInViewSpace(frame.common.worldToViewMatrix, m_Settings.lightDirection);
        c.gBlurRadiusScale = m_Settings.blurRadiusScale * kKernelRadiusPerPenumbraRadius;
        c.gPlaneDistanceSensitivity = m_Settings.planeDistanceSensitivity;
        c.gMaxStabilizedFrameNum = float(m_Settings.maxStabilizedFrameNum);
        SetShadowLightMotion(m_LightMotion, m_Settings, frame, c);

        // One constant block serves all passes (same layout, checked above).
        context.Dispatch(m_Classify, Cast<typename P::ClassifyTiles::Constants>(c), frame.width, frame.height);
        context.Dispatch(m_Smooth, Cast<passes::Sigma_SmoothTiles::Constants>(c), DivideUp(frame.width, 16),
                         DivideUp(frame.height, 16));
        context.Dispatch(m_Blur, c, frame.width, frame.height);
        context.Dispatch(isStabilized ? m_PostBlur : m_PostBlurToOutput, Cast<typename P::PostBlur::Constants>(c),
                         frame.width, frame.height);
        if (isStabilized)
        {
            context.Dispatch(m_Temporal[m_Parity], Cast<typename P::TemporalStabilization::Constants>(c), frame.width,
                             frame.height);
            m_Parity ^= 1u;
        }
        m_WasStabilized = isStabilized;
    }

private:
    template <class To, class From> static To Cast(const From& from)
    {
        static_assert(sizeof(To) == sizeof(From), "same layout");
        To to;
        std::memcpy(&to, &from, sizeof(To));
        return to;
    }

    SigmaSettings m_Settings = {};
    ShadowLightMotion m_LightMotion;
    uint32_t m_Classify = 0;
    uint32_t m_Smooth = 0;
    uint32_t m_Blur = 0;
    uint32_t m_PostBlur = 0;
    uint32_t m_PostBlurToOutput = 0;
    uint32_t m_Temporal[2] = {};
    uint32_t m_Parity = 0;
    bool m_WasStabilized = true;
};

} // namespace

std::unique_ptr<MethodBase> CreateSigma(MethodBuilder& builder, Method method)
{
    if (method == Method::SIGMA_SHADOW_TRANSLUCENCY)
        return std::unique_ptr<MethodBase>(new Sigma<ShadowTranslucencyPasses>(builder));
    return std::unique_ptr<MethodBase>(new Sigma<ShadowPasses>(builder));
}

} // namespace nrd
