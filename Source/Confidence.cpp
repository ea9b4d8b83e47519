// CONFIDENCE: history confidence from sparse temporal gradients (document 003, "Converting the
// Gradients into Confidence"; gradients after Schied et al. 2018, "Gradient Estimation for
// Real-Time Adaptive Temporal Filtering").
//
// Passes per frame:
//   Confidence_Filter    x atrousPassNum  a-trous 3x3 over IN_GRADIENTS at 1/3 resolution (steps 1, 2,
//                                         4, ...), ping-pong between two transient textures
//   Confidence_Local     x 0 or 1         the local limit's box means of IN_GRADIENTS at 1/3 resolution
//                                         (localGradientRadius > 0)
//   Confidence_Temporal  x 1              normalization, conversion to [0, 1], short temporal filter
//                                         with the reprojected history; writes OUT_*_CONFIDENCE
#include "InstanceImpl.h"

#include <cmath>

namespace nrd
{
namespace passes
{
NRD_PASS_TYPES
#include "../Shaders/Confidence/Confidence_Filter.resources.h"
#include "../Shaders/Confidence/Confidence_Local.resources.h"
#include "../Shaders/Confidence/Confidence_Temporal.resources.h"
} // namespace passes

namespace
{

constexpr uint16_t kStratumSize = 3; // Document 003: one gradient per 3x3 pixels.
// Confidence_Local.comp's shared tile holds an apron of CONFIDENCE_MAX_LOCAL_RADIUS (Confidence_Common.glsl).
static_assert(CONFIDENCE_MAX_LOCAL_GRADIENT_RADIUS == 8, "Confidence_Common.glsl: CONFIDENCE_MAX_LOCAL_RADIUS");

Result ValidateConfidenceSettings(const ConfidenceSettings& s, const Logger& log)
{
    struct FloatRange
    {
        const char* name;
        float value, lo, hi;
        bool isHiOpen;
    };
    const FloatRange floats[] = {
        {"gradientThreshold", s.gradientThreshold, 0.0f, 1.0f, true},
        {"gradientSensitivity", s.gradientSensitivity, 1.0f, 1000.0f, false},
        {"specularGradientSensitivity", s.specularGradientSensitivity, 1.0f, 1000.0f, false},
        {"fallHistoryWeight", s.fallHistoryWeight, 0.0f, 1.0f, true},
        {"riseHistoryWeight", s.riseHistoryWeight, 0.0f, 1.0f, true},
        {"depthThreshold", s.depthThreshold, 0.0f, 1.0f, false},
        {"normalPower", s.normalPower, 0.0f, 128.0f, false},
    };
    for (const FloatRange& r : floats)
    {
        // NaN fails every comparison, so it is rejected here too.
        bool inside = r.value >= r.lo && (r.isHiOpen ? r.value < r.hi : r.value <= r.hi);
        if (!inside)
        {
            log.Error("SetMethodSettings: ConfidenceSettings::%s %g is outside [%g, %g%c", r.name, double(r.value),
                      double(r.lo), double(r.hi), r.isHiOpen ? ')' : ']');
            return Result::INVALID_ARGUMENT;
        }
    }
    if (s.localGradientRadius > CONFIDENCE_MAX_LOCAL_GRADIENT_RADIUS)
    {
        log.Error("SetMethodSettings: ConfidenceSettings::localGradientRadius %u is outside [0, %u]", s.localGradientRadius,
                  CONFIDENCE_MAX_LOCAL_GRADIENT_RADIUS);
        return Result::INVALID_ARGUMENT;
    }
    if (s.atrousPassNum < 1 || s.atrousPassNum > CONFIDENCE_MAX_ATROUS_PASS_NUM)
    {
        log.Error("SetMethodSettings: ConfidenceSettings::atrousPassNum %u is outside [1, %u]", s.atrousPassNum,
                  CONFIDENCE_MAX_ATROUS_PASS_NUM);
        return Result::INVALID_ARGUMENT;
    }
    return Result::SUCCESS;
}

class Confidence final : public MethodBase
{
public:
    explicit Confidence(MethodBuilder& builder)
    {
        using R = ResourceType;
        // Filtered gradients (difference, luminance; diffuse, specular) at 1/3 resolution, only
        // within the frame: transient. Confidence history (diffuse, specular): permanent, two
        // copies written alternately.
        ResourceRef filtered[2] = {builder.AddTransientTexture(Format::RGBA16_SFLOAT, kStratumSize, kStratumSize),
                                   builder.AddTransientTexture(Format::RGBA16_SFLOAT, kStratumSize, kStratumSize)};
        // The local limit's box means of the unfiltered gradients, 1/3 resolution.
        const ResourceRef local = builder.AddTransientTexture(Format::RGBA16_SFLOAT, kStratumSize, kStratumSize);
        ResourceRef history[2] = {builder.AddPermanentTexture(Format::RG16_SFLOAT),
                                  builder.AddPermanentTexture(Format::RG16_SFLOAT)};
        const ResourceRef viewZ = App(R::IN_VIEWZ), normal = App(R::IN_NORMAL_ROUGHNESS);

        // One template per pass (a template runs at most once per frame): pass i reads what pass
        // i - 1 wrote, filtered[(i - 1) % 2] -> filtered[i % 2], the first reads IN_GRADIENTS.
        static const char* const kFilterNames[CONFIDENCE_MAX_ATROUS_PASS_NUM] = {
            "CONFIDENCE - Filter gradients (step 1)", "CONFIDENCE - Filter gradients (step 2)",
            "CONFIDENCE - Filter gradients (step 4)", "CONFIDENCE - Filter gradients (step 8)",
            "CONFIDENCE - Filter gradients (step 16)"};
        for (uint32_t i = 0; i < CONFIDENCE_MAX_ATROUS_PASS_NUM; i++)
            m_Filter[i] = builder.AddDispatch<passes::Confidence_Filter>(
                kFilterNames[i], {i == 0 ? App(R::IN_GRADIENTS) : filtered[(i - 1) & 1u], viewZ, normal, filtered[i & 1u]});
        m_Local = builder.AddDispatch<passes::Confidence_Local>("CONFIDENCE - Local gradients", {App(R::IN_GRADIENTS), local});
        for (int last = 0; last < 2; last++)
            for (int parity = 0; parity < 2; parity++)
                m_Temporal[last][parity] = builder.AddDispatch<passes::Confidence_Temporal>(
                    "CONFIDENCE - Temporal", {filtered[last], viewZ, App(R::IN_MV), history[parity], local,
                                              history[1 - parity], App(R::OUT_DIFF_CONFIDENCE), App(R::OUT_SPEC_CONFIDENCE)});
    }

    Result SetSettings(SettingsKind kind, const void* settings, const Logger& log) override
    {
        if (kind != SettingsKind::CONFIDENCE)
        {
            log.Error("SetMethodSettings: CONFIDENCE takes ConfidenceSettings");
            return Result::INVALID_ARGUMENT;
        }
        const ConfidenceSettings& s = *static_cast<const ConfidenceSettings*>(settings);
        Result result = ValidateConfidenceSettings(s, log);
        if (result == Result::SUCCESS)
            m_Settings = s;
        return result;
    }

    void Update(FrameContext& context) override
    {
        const FrameData& frame = context.Frame();
        const ConfidenceSettings& s = m_Settings;
        const uint32_t gradientWidth = DivideUp(frame.width, kStratumSize);
        const uint32_t gradientHeight = DivideUp(frame.height, kStratumSize);

        passes::Confidence_Filter::Constants f = {};
        context.FillCommonConstants(f);
        f.gGradientSize = {gradientWidth, gradientHeight};
        f.gDepthThreshold = s.depthThreshold;
        f.gNormalPower = s.normalPower;
        for (uint32_t i = 0; i < s.atrousPassNum; i++)
        {
            f.gStep = int32_t(1u << i);
            context.Dispatch(m_Filter[i], f, gradientWidth, gradientHeight);
        }

        if (s.localGradientRadius > 0)
        {
            passes::Confidence_Local::Constants l = {};
            context.FillCommonConstants(l);
            l.gGradientSize = {gradientWidth, gradientHeight};
            l.gRadius = int32_t(s.localGradientRadius);
            context.Dispatch(m_Local, l, gradientWidth, gradientHeight);
        }

        passes::Confidence_Temporal::Constants t = {};
        context.FillCommonConstants(t);
        t.gGradientSize = {gradientWidth, gradientHeight};
        t.gGradientThreshold = s.gradientThreshold;
        t.gGradientSensitivity = s.gradientSensitivity;
        t.gSpecularGradientSensitivity = s.specularGradientSensitivity;
        t.gFallHistoryWeight = s.fallHistoryWeight;
        t.gRiseHistoryWeight = s.riseHistoryWeight;
        t.gLocalRadius = s.localGradientRadius;
        const uint32_t last = (s.atrousPassNum - 1) & 1u;
        m_Parity = frame.resetHistory ? 0u : m_Parity ^ 1u;
        context.Dispatch(m_Temporal[last][m_Parity], t, frame.width, frame.height);
    }

private:
    ConfidenceSettings m_Settings = {};
    uint32_t m_Filter[CONFIDENCE_MAX_ATROUS_PASS_NUM] = {};
    uint32_t m_Local = 0;
    uint32_t m_Temporal[2][2] = {}; // [pool texture of the last filter pass][history parity]
    uint32_t m_Parity = 0;
};

} // namespace

std::unique_ptr<MethodBase> CreateConfidence(MethodBuilder& builder, Method)
{
    return std::unique_ptr<MethodBase>(new Confidence(builder));
}

} // namespace nrd
