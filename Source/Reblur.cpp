// REBLUR: recurrent-blur denoiser of diffuse / specular radiance and hit distance (document 004,
// REBLUR), REBLUR_DIFFUSE / _SPECULAR / _DIFFUSE_SPECULAR and the _OCCLUSION variants.
//
// Per frame, for a W x H input (each signal's chain runs after the other's, so that both share
// one transient texture):
//   1. Classify tiles        16x16 tiles with something to denoise (others are skipped by every
//                            pass); this frame's viewZ stored for the next (fp16, ping-pong).
//   per signal (diffuse, then specular):
//   2. Pre-pass (optional)   small spatial blur of the input (diffuse / specular / occlusionPrePassBlurRadius > 0).
//   3. Temporal accumulation slow + fast history along surface motion (specular: and virtual
//                            motion), anti-lag, confidence, checkerboard.
//   4. History fix           wide sparse reconstruction of short histories, anti-firefly.
//   5. Blur                  radius from history length, hit distance, roughness.
//   6. Post-blur             half radius, independently rotated; its result is the next history.
//   7. Temporal stabilization  luminance history clamped to the neighbourhood, anti-lag; output.
//
// Memory (bytes per pixel): permanent, per signal, history RGBA16F 8 + fast history and length
// RG16F 4 + stabilized luminance R16F 2 + debt R8 1 (confidence debt; diffuse: lighting change record), and viewZ R16F 2 x 2 (ping-pong);
// transient, shared by the
// signals, RGBA16F 8 and the 1/16 x 1/16 tile map. The application's output texture carries the
// temporal pass's auxiliary values (fast history, length, reprojected stabilized luminance) to the
// history fix before the final result is written into it.
#include "InstanceImpl.h"

#include <cmath>

namespace nrd
{
namespace passes
{
NRD_PASS_TYPES
#define REBLUR_SPECULAR 0
#define REBLUR_OCCLUSION 0
#include "../Shaders/Reblur/Reblur_TemporalAccumulation.resources.h"
#include "../Shaders/Reblur/Reblur_HistoryFix.resources.h"
#include "../Shaders/Reblur/Reblur_Blur.resources.h"
#include "../Shaders/Reblur/Reblur_TemporalStabilization.resources.h"
#undef REBLUR_SPECULAR
#define REBLUR_SPECULAR 1
#include "../Shaders/Reblur/Reblur_TemporalAccumulation.resources.h"
#include "../Shaders/Reblur/Reblur_HistoryFix.resources.h"
#include "../Shaders/Reblur/Reblur_Blur.resources.h"
#include "../Shaders/Reblur/Reblur_TemporalStabilization.resources.h"
#undef REBLUR_OCCLUSION
#define REBLUR_OCCLUSION 1
#include "../Shaders/Reblur/Reblur_TemporalAccumulation.resources.h"
#include "../Shaders/Reblur/Reblur_HistoryFix.resources.h"
#include "../Shaders/Reblur/Reblur_Blur.resources.h"
#include "../Shaders/Reblur/Reblur_TemporalStabilization.resources.h"
#undef REBLUR_SPECULAR
#define REBLUR_SPECULAR 0
#include "../Shaders/Reblur/Reblur_TemporalAccumulation.resources.h"
#include "../Shaders/Reblur/Reblur_HistoryFix.resources.h"
#include "../Shaders/Reblur/Reblur_Blur.resources.h"
#include "../Shaders/Reblur/Reblur_TemporalStabilization.resources.h"
#undef REBLUR_SPECULAR
#undef REBLUR_OCCLUSION
#include "../Shaders/Reblur/Reblur_ClassifyTiles.resources.h"
} // namespace passes

namespace
{

// Mirrors of Reblur_Constants.h.
constexpr uint32_t kFlagPrePass = 1;
constexpr uint32_t kFlagReference = 2;
constexpr uint32_t kFlagConfidence = 4;
constexpr uint16_t kTileSize = 16;

typedef passes::Reblur_Diffuse_TemporalAccumulation::Constants Constants;
static_assert(sizeof(Constants) % 16 == 0, "std140 block size");
static_assert(sizeof(Constants) == sizeof(passes::Reblur_ClassifyTiles::Constants) &&
                  sizeof(Constants) == sizeof(passes::Reblur_SpecularOcclusion_Blur::Constants) &&
                  sizeof(Constants) == sizeof(passes::Reblur_Specular_TemporalStabilization::Constants),
              "REBLUR passes share one constant block");

// The passes of one signal variant.
template <class TA, class HF, class BL, class TS, bool kOcclusion> struct Variant
{
    typedef TA TemporalAccumulation;
    typedef HF HistoryFix;
    typedef BL Blur;
    typedef TS TemporalStabilization;
    static constexpr bool kIsOcclusion = kOcclusion;
};

typedef Variant<passes::Reblur_Diffuse_TemporalAccumulation, passes::Reblur_Diffuse_HistoryFix,
                passes::Reblur_Diffuse_Blur, passes::Reblur_Diffuse_TemporalStabilization, false>
    DiffuseVariant;
typedef Variant<passes::Reblur_Specular_TemporalAccumulation, passes::Reblur_Specular_HistoryFix,
                passes::Reblur_Specular_Blur, passes::Reblur_Specular_TemporalStabilization, false>
    SpecularVariant;
typedef Variant<passes::Reblur_DiffuseOcclusion_TemporalAccumulation, passes::Reblur_DiffuseOcclusion_HistoryFix,
                passes::Reblur_DiffuseOcclusion_Blur, passes::Reblur_DiffuseOcclusion_TemporalStabilization, true>
    DiffuseOcclusionVariant;
typedef Variant<passes::Reblur_SpecularOcclusion_TemporalAccumulation, passes::Reblur_SpecularOcclusion_HistoryFix,
                passes::Reblur_SpecularOcclusion_Blur, passes::Reblur_SpecularOcclusion_TemporalStabilization, true>
    SpecularOcclusionVariant;

template <class To> To Cast(const Constants& from)
{
    static_assert(sizeof(To) == sizeof(Constants), "same layout");
    To to;
    std::memcpy(&to, &from, sizeof(To));
    return to;
}

Result ValidateReblurSettings(const ReblurSettings& s, const Logger& log)
{
    if (ValidateHitDistanceParameters(s.hitDistanceParameters, "ReblurSettings::hitDistanceParameters", log) !=
        Result::SUCCESS)
        return Result::INVALID_ARGUMENT;
    struct UintRange
    {
        const char* name;
        uint32_t value, hi;
    };
    const UintRange uints[] = {
        {"maxAccumulatedFrameNum", s.maxAccumulatedFrameNum, REBLUR_MAX_HISTORY_FRAME_NUM},
        {"maxFastAccumulatedFrameNum", s.maxFastAccumulatedFrameNum, s.maxAccumulatedFrameNum},
        {"historyFixFrameNum", s.historyFixFrameNum, REBLUR_MAX_HISTORY_FIX_FRAME_NUM},
        {"maxStabilizedFrameNum", s.maxStabilizedFrameNum, REBLUR_MAX_HISTORY_FRAME_NUM},
    };
    for (const UintRange& r : uints)
    {
        if (r.value > r.hi)
        {
            log.Error("SetMethodSettings: ReblurSettings::%s %u is outside [0, %u]", r.name, r.value, r.hi);
            return Result::INVALID_ARGUMENT;
        }
    }
    struct FloatRange
    {
        const char* name;
        float value, lo, hi;
        bool isLoOpen;
    };
    const FloatRange floats[] = {
        {"historyFixStride", s.historyFixStride, 1.0f, 16.0f, false},
        {"blurRadius", s.blurRadius, 0.0f, REBLUR_MAX_BLUR_RADIUS, false},
        {"minBlurRadius", s.minBlurRadius, 0.0f, s.blurRadius, false},
        {"diffusePrePassBlurRadius", s.diffusePrePassBlurRadius, 0.0f, REBLUR_MAX_BLUR_RADIUS, false},
        {"specularPrePassBlurRadius", s.specularPrePassBlurRadius, 0.0f, REBLUR_MAX_BLUR_RADIUS, false},
        {"occlusionPrePassBlurRadius", s.occlusionPrePassBlurRadius, 0.0f, REBLUR_MAX_BLUR_RADIUS, false},
        {"postBlurRadiusScale", s.postBlurRadiusScale, 0.0f, 2.0f, false},
        {"planeDistanceSensitivity", s.planeDistanceSensitivity, 0.0f, 1.0f, true},
        {"lobeAngleFraction", s.lobeAngleFraction, 0.0f, 4.0f, true},
        {"roughnessFraction", s.roughnessFraction, 0.0f, 1.0f, true},
        {"antilagSigmaScale", s.antilagSigmaScale, 0.5f, 64.0f, false},
        {"colorCompression", s.colorCompression, 0.0f, 16.0f, false},
        {"antiFireflySigma", s.antiFireflySigma, 0.0f, 64.0f, false},
    };
    for (const FloatRange& r : floats)
    {
        bool isAboveLo = r.isLoOpen ? r.value > r.lo : r.value >= r.lo;
        if (!(isAboveLo && r.value <= r.hi)) // NaN fails too.
        {
            log.Error("SetMethodSettings: ReblurSettings::%s %g is outside %c%g, %g]", r.name, double(r.value),
                      r.isLoOpen ? '(' : '[', double(r.lo), double(r.hi));
            return Result::INVALID_ARGUMENT;
        }
    }
    if (uint32_t(s.checkerboardMode) > uint32_t(CheckerboardMode::WHITE))
    {
        log.Error("SetMethodSettings: ReblurSettings::checkerboardMode %u is unknown", uint32_t(s.checkerboardMode));
        return Result::INVALID_ARGUMENT;
    }
    return Result::SUCCESS;
}

// Dispatch templates of one signal (diffuse or specular).
struct Chain
{
    uint32_t prePass = 0;
    uint32_t temporal[2][2] = {}; // [frame parity][confidence input]
    uint32_t historyFix = 0;
    uint32_t blur = 0;
    uint32_t postBlur = 0;
    uint32_t stabilization = 0;
    bool isSpecular = false;
};

class Reblur final : public MethodBase
{
public:
    Reblur(MethodBuilder& builder, Method method)
    {
        const bool isOcclusion = method == Method::REBLUR_DIFFUSE_OCCLUSION || method == Method::REBLUR_SPECULAR_OCCLUSION ||
                                 method == Method::REBLUR_DIFFUSE_SPECULAR_OCCLUSION;
        const bool hasDiffuse = method == Method::REBLUR_DIFFUSE || method == Method::REBLUR_DIFFUSE_SPECULAR ||
                                method == Method::REBLUR_DIFFUSE_OCCLUSION ||
                                method == Method::REBLUR_DIFFUSE_SPECULAR_OCCLUSION;
        const bool hasSpecular = method == Method::REBLUR_SPECULAR || method == Method::REBLUR_DIFFUSE_SPECULAR ||
                                 method == Method::REBLUR_SPECULAR_OCCLUSION ||
                                 method == Method::REBLUR_DIFFUSE_SPECULAR_OCCLUSION;

        m_IsOcclusion = isOcclusion;
        const ResourceRef viewZ = App(ResourceType::IN_VIEWZ);
        for (int i = 0; i < 2; i++)
            m_ViewZ[i] = builder.AddPermanentTexture(Format::R16_SFLOAT);
        m_Tiles = builder.AddTransientTexture(Format::R8_UNORM, kTileSize, kTileSize);
        m_Signal = builder.AddTransientTexture(Format::RGBA16_SFLOAT);
        for (int i = 0; i < 2; i++)
            m_Classify[i] = builder.AddDispatch<passes::Reblur_ClassifyTiles>("REBLUR - Classify tiles",
                                                                              {viewZ, m_Tiles, m_ViewZ[i]});

        if (hasDiffuse)
        {
            if (isOcclusion)
                AddChain<DiffuseOcclusionVariant>(builder, false, ResourceType::IN_DIFF_HITDIST,
                                                  ResourceType::OUT_DIFF_HITDIST);
            else
                AddChain<DiffuseVariant>(builder, false, ResourceType::IN_DIFF_RADIANCE_HITDIST,
                                         ResourceType::OUT_DIFF_RADIANCE_HITDIST);
        }
        if (hasSpecular)
        {
            if (isOcclusion)
                AddChain<SpecularOcclusionVariant>(builder, true, ResourceType::IN_SPEC_HITDIST,
                                                   ResourceType::OUT_SPEC_HITDIST);
            else
                AddChain<SpecularVariant>(builder, true, ResourceType::IN_SPEC_RADIANCE_HITDIST,
                                          ResourceType::OUT_SPEC_RADIANCE_HITDIST);
        }
    }

    Result SetSettings(SettingsKind kind, const void* settings, const Logger& log) override
    {
        if (kind != SettingsKind::REBLUR)
        {
            log.Error("SetMethodSettings: REBLUR_* methods take ReblurSettings");
            return Result::INVALID_ARGUMENT;
        }
        const ReblurSettings& s = *static_cast<const ReblurSettings*>(settings);
        Result result = ValidateReblurSettings(s, log);
        if (result == Result::SUCCESS)
            m_Settings = s;
        return result;
    }

    void Update(FrameContext& context) override
    {
        const FrameData& frame = context.Frame();
        const ReblurSettings& s = m_Settings;

        Constants c = {};
        context.FillCommonConstants(c);
        // Turning reference accumulation on or off changes what the history means.
        if (s.forceReferenceAccumulation != m_WasReference || s.maxAccumulatedFrameNum == 0)
            c.gResetHistory = 1u;
        const HitDistanceParameters& h = s.hitDistanceParameters;
        c.gHitDistParams = {h.A, h.B, h.C, h.D};
        c.gMaxAccumulatedFrameNum = float(s.maxAccumulatedFrameNum);
        c.gMaxFastAccumulatedFrameNum = float(s.maxFastAccumulatedFrameNum);
        c.gHistoryFixFrameNum = float(s.historyFixFrameNum);
        c.gHistoryFixStride = s.historyFixStride;
        c.gBlurRadius = s.blurRadius;
        c.gMinBlurRadius = s.minBlurRadius;
        c.gPassRadiusScale = 1.0f;
        c.gPlaneDistanceSensitivity = s.planeDistanceSensitivity;
        c.gLobeAngleFraction = s.lobeAngleFraction;
        c.gRoughnessFraction = s.roughnessFraction;
        c.gAntilagSigmaScale = s.antilagSigmaScale;
        c.gStabilizationFrameNum = float(s.maxStabilizedFrameNum);
        c.gColorCompression = s.colorCompression;
        c.gFireflyScale = s.antiFireflySigma;
        c.gFlags = (s.forceReferenceAccumulation ? kFlagReference : 0u) | (s.isConfidenceInput ? kFlagConfidence : 0u);
        if (s.checkerboardMode != CheckerboardMode::OFF)
        {
            uint32_t parity = (frame.common.frameIndex + (s.checkerboardMode == CheckerboardMode::WHITE ? 1u : 0u)) & 1u;
            c.gCheckerboard = 1u + parity;
        }

        const uint32_t w = frame.width, h2 = frame.height;
        context.Dispatch(m_Classify[m_Parity], Cast<passes::Reblur_ClassifyTiles::Constants>(c), w, h2);
        for (uint32_t i = 0; i < m_ChainsNum; i++)
        {
            const Chain& chain = m_Chains[i];
            Constants p = c;
            const float prePassRadius = m_IsOcclusion     ? s.occlusionPrePassBlurRadius
                                        : chain.isSpecular ? s.specularPrePassBlurRadius
                                                           : s.diffusePrePassBlurRadius;
            const bool isPrePass = prePassRadius > 0.0f && !s.forceReferenceAccumulation;
            if (isPrePass)
            {
                p.gPassIndex = 0;
                p.gBlurRadius = prePassRadius; // Absolute: history length reads as 0 there.
                p.gPassRadiusScale = 1.0f;
                context.Dispatch(chain.prePass, p, w, h2);
            }
            p = c;
            p.gFlags |= isPrePass ? kFlagPrePass : 0u;
            context.Dispatch(chain.temporal[m_Parity][s.isConfidenceInput ? 1 : 0], p, w, h2);
            context.Dispatch(chain.historyFix, p, w, h2);
            p.gPassIndex = 1;
            p.gPassRadiusScale = s.forceReferenceAccumulation ? 0.0f : 1.0f;
            context.Dispatch(chain.blur, p, w, h2);
            p.gPassIndex = 2;
            p.gPassRadiusScale = s.forceReferenceAccumulation ? 0.0f : s.postBlurRadiusScale;
            context.Dispatch(chain.postBlur, p, w, h2);
            p.gPassIndex = 0;
            p.gPassRadiusScale = 1.0f;
            context.Dispatch(chain.stabilization, p, w, h2);
        }
        m_Parity ^= 1u;
        m_WasReference = s.forceReferenceAccumulation;
    }

private:
    template <class V>
    void AddChain(MethodBuilder& builder, bool isSpecular, ResourceType input, ResourceType output)
    {
        typedef typename V::TemporalAccumulation TA;
        typedef typename V::HistoryFix HF;
        typedef typename V::Blur BL;
        typedef typename V::TemporalStabilization TS;
        const ResourceRef normal = App(ResourceType::IN_NORMAL_ROUGHNESS);
        const ResourceRef viewZ = App(ResourceType::IN_VIEWZ);
        const ResourceRef mv = App(ResourceType::IN_MV);
        const ResourceRef in = App(input);
        const ResourceRef out = App(output);
        const ResourceRef confidence =
            App(isSpecular ? ResourceType::IN_SPEC_CONFIDENCE : ResourceType::IN_DIFF_CONFIDENCE);
        const ResourceRef history = builder.AddPermanentTexture(Format::RGBA16_SFLOAT);
        const ResourceRef fast = builder.AddPermanentTexture(Format::RG16_SFLOAT);
        const ResourceRef stabilized = builder.AddPermanentTexture(Format::R16_SFLOAT);
        // Debt: specular and occlusion, the frames of history the confidence input took (keeps the history
        // fix off); diffuse radiance, the lighting change record and residual (Reblur_Common.glsl).
        const ResourceRef debt = builder.AddPermanentTexture(Format::R8_UNORM);

        Chain& chain = m_Chains[m_ChainsNum++];
        chain.isSpecular = isSpecular;
        chain.prePass = builder.AddDispatch<BL>(Name(isSpecular, 0), {normal, viewZ, m_Tiles, fast, in, m_Signal, debt});
        for (int parity = 0; parity < 2; parity++)
        {
            // Frame parity p reads the viewZ stored by the other parity's classification.
            const ResourceRef prevViewZ = m_ViewZ[1 - parity];
            for (int withConfidence = 0; withConfidence < 2; withConfidence++)
            {
                // Without confidence input the slot holds viewZ (never read: the flag is off).
                const ResourceRef conf = withConfidence ? confidence : viewZ;
                if constexpr (V::kIsOcclusion)
                    chain.temporal[parity][withConfidence] = builder.AddDispatch<TA>(
                        Name(isSpecular, 1),
                        {normal, viewZ, mv, in, conf, m_Tiles, prevViewZ, history, fast, stabilized, m_Signal, debt});
                else
                    chain.temporal[parity][withConfidence] = builder.AddDispatch<TA>(
                        Name(isSpecular, 1),
                        {normal, viewZ, mv, in, conf, m_Tiles, prevViewZ, history, fast, stabilized, m_Signal, out, debt});
            }
        }
        if constexpr (V::kIsOcclusion)
            chain.historyFix = builder.AddDispatch<HF>(Name(isSpecular, 2),
                                                       {normal, viewZ, m_Tiles, m_Signal, history, fast, stabilized, debt});
        else
            chain.historyFix = builder.AddDispatch<HF>(
                Name(isSpecular, 2), {normal, viewZ, m_Tiles, m_Signal, out, history, fast, stabilized, debt});
        // The history keeps the temporally accumulated signal: the blurs go through the output
        // texture and the transient one, so that no frame's spatial filtering is carried into the
        // next frames (a recurrent blur widens the effective kernel with every frame).
        chain.blur = builder.AddDispatch<BL>(Name(isSpecular, 3), {normal, viewZ, m_Tiles, fast, history, out, debt});
        chain.postBlur = builder.AddDispatch<BL>(Name(isSpecular, 4), {normal, viewZ, m_Tiles, fast, out, m_Signal, debt});
        chain.stabilization =
            builder.AddDispatch<TS>(Name(isSpecular, 5), {normal, viewZ, m_Tiles, m_Signal, fast, stabilized, out});
    }

    static const char* Name(bool isSpecular, int pass)
    {
        static const char* const kNames[2][6] = {
            {"REBLUR diffuse - Pre-pass", "REBLUR diffuse - Temporal accumulation", "REBLUR diffuse - History fix",
             "REBLUR diffuse - Blur", "REBLUR diffuse - Post-blur", "REBLUR diffuse - Temporal stabilization"},
            {"REBLUR specular - Pre-pass", "REBLUR specular - Temporal accumulation", "REBLUR specular - History fix",
             "REBLUR specular - Blur", "REBLUR specular - Post-blur", "REBLUR specular - Temporal stabilization"}};
        return kNames[isSpecular ? 1 : 0][pass];
    }

    ReblurSettings m_Settings = {};
    ResourceRef m_ViewZ[2];
    ResourceRef m_Tiles;
    ResourceRef m_Signal;
    uint32_t m_Classify[2] = {};
    Chain m_Chains[2];
    uint32_t m_ChainsNum = 0;
    uint32_t m_Parity = 0;
    bool m_WasReference = false;
    bool m_IsOcclusion = false;
};

} // namespace

std::unique_ptr<MethodBase> CreateReblur(MethodBuilder& builder, Method method)
{
    return std::unique_ptr<MethodBase>(new Reblur(builder, method));
}

} // namespace nrd
