// RELAX: SVGF-style radiance denoisers with fast-history clamping, RELAX_DIFFUSE, RELAX_SPECULAR and
// RELAX_DIFFUSE_SPECULAR (document 004; Schied et al. 2017, "Spatiotemporal Variance-Guided
// Filtering"; Dammertz et al. 2010, "Edge-Avoiding A-Trous Wavelet Transform").
//
// Per frame, for a W x H input (one chain per signal, the diffuse chain first):
//   1. Classify tiles          8x8 tiles holding no pixel to denoise (sky) are skipped by the rest.
//   2. Temporal accumulation   reprojection with per-tap disocclusion, slow and fast histories,
//                              second luminance moment, anti-lag from this frame's 5x5 input mean.
//   3. History fix             short histories rebuilt from neighbours; anti-firefly; slow history
//                              clamped to the fast one's 3x3 neighbourhood; writes the histories
//                              (and, in the last chain, viewZ for the next frame).
//   4. Variance estimation     temporal moments, 7x7 spatial while the history is short.
//   5. A-trous                 atrousIterationNum iterations, steps 1, 2, 4, ...; the first from
//                              shared memory, the last writes OUT_*_RADIANCE_HITDIST.
//
// Memory (bytes per pixel): per signal, permanent slow history RGBA16F (radiance, hit distance),
// fast history RGBA16F (fast radiance, sqrt of the second moment), RG8 (history length and confidence
// debt; lighting change record and residual: Relax_Common.glsl) = 18; shared permanent viewZ R16F = 2; transient, shared by the chains (they run one after
// the other): one RGBA16F and one RG8 = 10, plus the 1/8 x 1/8 tile map. The application's output texture carries the
// temporal pass's fast history to the history fix and is the a-trous iterations' second ping-pong
// buffer before the final result is written into it.
#include "InstanceImpl.h"

#include <cmath>

namespace nrd
{
namespace passes
{
NRD_PASS_TYPES
#include "../Shaders/Relax/Relax_Constants.h"
#include "../Shaders/Relax/Relax_ClassifyTiles.resources.h"
#include "../Shaders/Relax/Relax_SpatialVariance.resources.h"
#define RELAX_SPECULAR 0
#define RELAX_CONFIDENCE 0
#define RELAX_ATROUS_SMEM 0
#include "../Shaders/Relax/Relax_TemporalAccumulation.resources.h"
#include "../Shaders/Relax/Relax_HistoryFix.resources.h"
#include "../Shaders/Relax/Relax_Atrous.resources.h"
#undef RELAX_CONFIDENCE
#define RELAX_CONFIDENCE 1
#include "../Shaders/Relax/Relax_TemporalAccumulation.resources.h"
#undef RELAX_ATROUS_SMEM
#define RELAX_ATROUS_SMEM 1
#include "../Shaders/Relax/Relax_Atrous.resources.h"
#undef RELAX_SPECULAR
#define RELAX_SPECULAR 1
#include "../Shaders/Relax/Relax_Atrous.resources.h"
#undef RELAX_ATROUS_SMEM
#define RELAX_ATROUS_SMEM 0
#include "../Shaders/Relax/Relax_Atrous.resources.h"
#include "../Shaders/Relax/Relax_HistoryFix.resources.h"
#include "../Shaders/Relax/Relax_TemporalAccumulation.resources.h"
#undef RELAX_CONFIDENCE
#define RELAX_CONFIDENCE 0
#include "../Shaders/Relax/Relax_TemporalAccumulation.resources.h"
#undef RELAX_SPECULAR
#undef RELAX_CONFIDENCE
#undef RELAX_ATROUS_SMEM
} // namespace passes

namespace
{

constexpr uint32_t kTileSize = 8;
constexpr uint32_t kMaxAtrousIterationNum = 8;

typedef passes::Relax_ClassifyTiles::Constants RelaxConstants;
static_assert(sizeof(RelaxConstants) == sizeof(passes::Relax_Diffuse_TemporalAccumulation::Constants) &&
                  sizeof(RelaxConstants) == sizeof(passes::Relax_Specular_AtrousSmem::Constants) &&
                  sizeof(RelaxConstants) == sizeof(passes::Relax_SpatialVariance::Constants),
              "RELAX passes share one constant block");
static_assert(sizeof(RelaxConstants) % 16 == 0, "std140 block size");
static_assert(RELAX_MAX_HISTORY_FRAME_NUM <= 63, "history lengths are stored in 6 bits of UNORM8 (RELAX_HISTORY_LENGTH_LIMIT)");

template <class To> To Cast(const RelaxConstants& from)
{
    static_assert(sizeof(To) == sizeof(RelaxConstants), "same layout");
    To to;
    std::memcpy(&to, &from, sizeof(To));
    return to;
}

bool InRange(float x, float lo, float hi, bool loOpen) { return (loOpen ? x > lo : x >= lo) && x <= hi; }

Result ValidateRelaxSettings(const RelaxSettings& s, const Logger& log)
{
    Result hitDistance = ValidateHitDistanceParameters(s.hitDistanceParameters, "RelaxSettings::hitDistanceParameters", log);
    if (hitDistance != Result::SUCCESS)
        return hitDistance;
    struct FloatCheck
    {
        const char* name;
        float value, lo, hi;
        bool loOpen;
    };
    const FloatCheck floats[] = {
        {"historyFixStride", s.historyFixStride, 1.0f, 32.0f, false},
        {"diffuseHistoryClampingColorBoxSigmaScale", s.diffuseHistoryClampingColorBoxSigmaScale, 0.5f, 4.0f, false},
        {"specularHistoryClampingColorBoxSigmaScale", s.specularHistoryClampingColorBoxSigmaScale, 0.5f, 4.0f, false},
        {"antilagSigmaScale", s.antilagSigmaScale, 0.0f, 16.0f, false},
        {"diffusePhiLuminance", s.diffusePhiLuminance, 0.0f, 16.0f, true},
        {"specularPhiLuminance", s.specularPhiLuminance, 0.0f, 16.0f, true},
        {"diffuseLobeAngleFraction", s.diffuseLobeAngleFraction, 0.0f, 1.0f, true},
        {"specularLobeAngleFraction", s.specularLobeAngleFraction, 0.0f, 1.0f, true},
        {"specularLobeAngleSlack", s.specularLobeAngleSlack, 0.0f, 90.0f, false},
        {"roughnessFraction", s.roughnessFraction, 0.0f, 1.0f, true},
        {"depthThreshold", s.depthThreshold, 0.0f, 1.0f, true},
    };
    for (const FloatCheck& f : floats)
    {
        if (!InRange(f.value, f.lo, f.hi, f.loOpen))
        {
            log.Error("SetMethodSettings: RelaxSettings::%s %g is outside %c%g, %g]", f.name, double(f.value),
                      f.loOpen ? '(' : '[', double(f.lo), double(f.hi));
            return Result::INVALID_ARGUMENT;
        }
    }
    struct UintCheck
    {
        const char* name;
        uint32_t value, lo, hi;
    };
    const UintCheck uints[] = {
        {"diffuseMaxAccumulatedFrameNum", s.diffuseMaxAccumulatedFrameNum, 0, RELAX_MAX_HISTORY_FRAME_NUM},
        {"specularMaxAccumulatedFrameNum", s.specularMaxAccumulatedFrameNum, 0, RELAX_MAX_HISTORY_FRAME_NUM},
        {"diffuseMaxFastAccumulatedFrameNum", s.diffuseMaxFastAccumulatedFrameNum, 0, s.diffuseMaxAccumulatedFrameNum},
        {"specularMaxFastAccumulatedFrameNum", s.specularMaxFastAccumulatedFrameNum, 0, s.specularMaxAccumulatedFrameNum},
        {"historyFixFrameNum", s.historyFixFrameNum, 0, 3},
        {"spatialVarianceEstimationHistoryThreshold", s.spatialVarianceEstimationHistoryThreshold, 0,
         RELAX_MAX_HISTORY_FRAME_NUM},
        {"atrousIterationNum", s.atrousIterationNum, 2, kMaxAtrousIterationNum},
    };
    for (const UintCheck& u : uints)
    {
        if (u.value < u.lo || u.value > u.hi)
        {
            log.Error("SetMethodSettings: RelaxSettings::%s %u is outside [%u, %u]", u.name, u.value, u.lo, u.hi);
            return Result::INVALID_ARGUMENT;
        }
    }
    if (uint32_t(s.checkerboardMode) > uint32_t(CheckerboardMode::WHITE))
    {
        log.Error("SetMethodSettings: RelaxSettings::checkerboardMode %u is not a CheckerboardMode value",
                  uint32_t(s.checkerboardMode));
        return Result::INVALID_ARGUMENT;
    }
    return Result::SUCCESS;
}

// The dispatch templates of one signal.
struct Chain
{
    bool isSpecular = false;
    uint32_t temporal[2] = {}; // Without / with the confidence input.
    uint32_t historyFix = 0;
    uint32_t variance[2] = {};   // [0] -> transient, [1] -> output.
    // Per iteration k ([0]: shared memory), since a template runs at most once per frame:
    // [k][0] transient -> output, [k][1] output -> transient.
    uint32_t atrous[kMaxAtrousIterationNum][2] = {};
};

class Relax final : public MethodBase
{
public:
    Relax(MethodBuilder& builder, Method method)
    {
        const ResourceRef normal = App(ResourceType::IN_NORMAL_ROUGHNESS);
        const ResourceRef viewZ = App(ResourceType::IN_VIEWZ);
        const ResourceRef mv = App(ResourceType::IN_MV);

        m_Tiles = builder.AddTransientTexture(Format::R8_UNORM, kTileSize, kTileSize);
        const ResourceRef transient = builder.AddTransientTexture(Format::RGBA16_SFLOAT);
        const ResourceRef transientLength = builder.AddTransientTexture(Format::RG8_UNORM);
        const ResourceRef prevViewZ = builder.AddPermanentTexture(Format::R16_SFLOAT);
        m_Classify = builder.AddDispatch<passes::Relax_ClassifyTiles>("RELAX - Classify tiles", {viewZ, m_Tiles});

        const bool hasDiffuse = method != Method::RELAX_SPECULAR;
        const bool hasSpecular = method != Method::RELAX_DIFFUSE;
        for (int signal = 0; signal < 2; signal++)
        {
            const bool isSpecular = signal == 1;
            if ((isSpecular && !hasSpecular) || (!isSpecular && !hasDiffuse))
                continue;
            const ResourceRef slow = builder.AddPermanentTexture(Format::RGBA16_SFLOAT);
            const ResourceRef fast = builder.AddPermanentTexture(Format::RGBA16_SFLOAT);
            // .x: history length and confidence debt (the frames the confidence input took); .y: the
            // diffuse lighting change record and residual (Shaders/Relax/Relax_Common.glsl).
            const ResourceRef length = builder.AddPermanentTexture(Format::RG8_UNORM);
            const ResourceRef input =
                App(isSpecular ? ResourceType::IN_SPEC_RADIANCE_HITDIST : ResourceType::IN_DIFF_RADIANCE_HITDIST);
            const ResourceRef confidence = App(isSpecular ? ResourceType::IN_SPEC_CONFIDENCE : ResourceType::IN_DIFF_CONFIDENCE);
            const ResourceRef output =
                App(isSpecular ? ResourceType::OUT_SPEC_RADIANCE_HITDIST : ResourceType::OUT_DIFF_RADIANCE_HITDIST);
            // The output texture holds the fast history between the temporal pass and the history fix.
            const std::initializer_list<ResourceRef> temporal = {normal, viewZ, mv, input, m_Tiles, prevViewZ, slow, fast,
                                                                 length, transient, output, transientLength};
            const std::initializer_list<ResourceRef> temporalConfidence = {
                normal, viewZ, mv, input, m_Tiles, prevViewZ, slow, fast, length, transient, output, transientLength,
                confidence};
            const std::initializer_list<ResourceRef> fix = {normal, viewZ, m_Tiles, transient, output,
                                                            transientLength, slow, fast, length, prevViewZ};
            const std::initializer_list<ResourceRef> varianceToTransient = {normal, viewZ, m_Tiles, slow, fast, length, transient};
            const std::initializer_list<ResourceRef> varianceToOutput = {normal, viewZ, m_Tiles, slow, fast, length, output};
            const std::initializer_list<ResourceRef> toOutput = {normal, viewZ, m_Tiles, transient, slow, output};
            const std::initializer_list<ResourceRef> toTransient = {normal, viewZ, m_Tiles, output, slow, transient};

            Chain chain;
            chain.isSpecular = isSpecular;
            const char* varianceName = isSpecular ? "RELAX - Specular variance estimation" : "RELAX - Diffuse variance estimation";
            chain.variance[0] = builder.AddDispatch<passes::Relax_SpatialVariance>(varianceName, varianceToTransient);
            chain.variance[1] = builder.AddDispatch<passes::Relax_SpatialVariance>(varianceName, varianceToOutput);
            if (isSpecular)
            {
                chain.temporal[0] = builder.AddDispatch<passes::Relax_Specular_TemporalAccumulation>(
                    "RELAX - Specular temporal accumulation", temporal);
                chain.temporal[1] = builder.AddDispatch<passes::Relax_Specular_TemporalAccumulationConfidence>(
                    "RELAX - Specular temporal accumulation", temporalConfidence);
                chain.historyFix = builder.AddDispatch<passes::Relax_Specular_HistoryFix>(
                    "RELAX - Specular history fix and clamping", fix);
                for (int d = 0; d < 2; d++)
                {
                    chain.atrous[0][d] = builder.AddDispatch<passes::Relax_Specular_AtrousSmem>(
                        "RELAX - Specular a-trous (shared memory)", d == 0 ? toOutput : toTransient);
                    for (uint32_t k = 1; k < kMaxAtrousIterationNum; k++)
                        chain.atrous[k][d] =
                            builder.AddDispatch<passes::Relax_Specular_Atrous>("RELAX - Specular a-trous", d == 0 ? toOutput : toTransient);
                }
            }
            else
            {
                chain.temporal[0] = builder.AddDispatch<passes::Relax_Diffuse_TemporalAccumulation>(
                    "RELAX - Diffuse temporal accumulation", temporal);
                chain.temporal[1] = builder.AddDispatch<passes::Relax_Diffuse_TemporalAccumulationConfidence>(
                    "RELAX - Diffuse temporal accumulation", temporalConfidence);
                chain.historyFix = builder.AddDispatch<passes::Relax_Diffuse_HistoryFix>(
                    "RELAX - Diffuse history fix and clamping", fix);
                for (int d = 0; d < 2; d++)
                {
                    chain.atrous[0][d] = builder.AddDispatch<passes::Relax_Diffuse_AtrousSmem>(
                        "RELAX - Diffuse a-trous (shared memory)", d == 0 ? toOutput : toTransient);
                    for (uint32_t k = 1; k < kMaxAtrousIterationNum; k++)
                        chain.atrous[k][d] =
                            builder.AddDispatch<passes::Relax_Diffuse_Atrous>("RELAX - Diffuse a-trous", d == 0 ? toOutput : toTransient);
                }
            }
            m_Chains[m_ChainNum++] = chain;
        }
    }

    Result SetSettings(SettingsKind kind, const void* settings, const Logger& log) override
    {
        if (kind != SettingsKind::RELAX)
        {
            log.Error("SetMethodSettings: RELAX_* methods take RelaxSettings");
            return Result::INVALID_ARGUMENT;
        }
        const RelaxSettings& s = *static_cast<const RelaxSettings*>(settings);
        Result result = ValidateRelaxSettings(s, log);
        if (result == Result::SUCCESS)
            m_Settings = s;
        return result;
    }

    void Update(FrameContext& context) override
    {
        const FrameData& frame = context.Frame();
        const RelaxSettings& s = m_Settings;
        constexpr float kDegToRad = 3.14159265358979f / 180.0f;

        RelaxConstants c = {};
        context.FillCommonConstants(c);
        const HitDistanceParameters& hd = s.hitDistanceParameters;
        c.gHitDistParams = {hd.A, hd.B, hd.C, hd.D};
        c.gHistoryFixFrameNum = float(s.historyFixFrameNum);
        c.gHistoryFixStride = s.historyFixStride;
        c.gAntilagSigma = s.antilagSigmaScale;
        c.gRoughnessFraction = s.roughnessFraction;
        c.gDepthThreshold = s.depthThreshold;
        c.gVarianceHistoryThreshold = float(s.spatialVarianceEstimationHistoryThreshold);
        c.gCheckerboard = s.checkerboardMode == CheckerboardMode::OFF ? 0u
                          : s.checkerboardMode == CheckerboardMode::BLACK ? 2u : 1u;
        context.Dispatch(m_Classify, c, DivideUp(frame.width, kTileSize) * kTileSize,
                         DivideUp(frame.height, kTileSize) * kTileSize);

        for (uint32_t i = 0; i < m_ChainNum; i++)
        {
            const Chain& chain = m_Chains[i];
            const bool isLastChain = i + 1 == m_ChainNum;
            if (chain.isSpecular)
            {
                c.gMaxAccumulatedFrameNum = float(s.specularMaxAccumulatedFrameNum);
                c.gMaxFastAccumulatedFrameNum = float(s.specularMaxFastAccumulatedFrameNum);
                c.gPhiLuminance = s.specularPhiLuminance;
                c.gHistoryClampSigma = s.specularHistoryClampingColorBoxSigmaScale;
                c.gLobeAngleFraction = s.specularLobeAngleFraction;
                c.gLobeAngleSlack = s.specularLobeAngleSlack * kDegToRad;
            }
            else
            {
                c.gMaxAccumulatedFrameNum = float(s.diffuseMaxAccumulatedFrameNum);
                c.gMaxFastAccumulatedFrameNum = float(s.diffuseMaxFastAccumulatedFrameNum);
                c.gHistoryClampSigma = s.diffuseHistoryClampingColorBoxSigmaScale;
                c.gPhiLuminance = s.diffusePhiLuminance;
                c.gLobeAngleFraction = s.diffuseLobeAngleFraction;
                c.gLobeAngleSlack = 0.0f;
            }
            const uint32_t w = frame.width, h = frame.height;
            c.gFlags = s.useConfidenceInputs ? RELAX_FLAG_CONFIDENCE : 0u;
            context.Dispatch(chain.temporal[s.useConfidenceInputs ? 1 : 0], c, w, h);
            c.gFlags = (s.enableAntiFirefly ? RELAX_FLAG_ANTI_FIREFLY : 0u) | (isLastChain ? RELAX_FLAG_WRITE_VIEWZ : 0u);
            context.Dispatch(chain.historyFix, c, w, h);
            // The iterations alternate between the transient texture and the output so that the
            // last one (k = N - 1) reads the transient and writes the output: iteration k writes the
            // output where N - 1 - k is even.
            const uint32_t n = s.atrousIterationNum;
            c.gFlags = 0u;
            context.Dispatch(chain.variance[((n - 1) & 1u) == 0u ? 0 : 1], c, w, h);
            const uint32_t baseFlags = s.enableRoughnessEdgeStopping ? RELAX_FLAG_ROUGHNESS_STOP : 0u;
            for (uint32_t k = 0; k < n; k++)
            {
                const int toTransient = ((n - 1 - k) & 1u) == 0u ? 0 : 1;
                c.gAtrousStep = 1u << k;
                c.gFlags = baseFlags | (k + 1 == n ? RELAX_FLAG_LAST_ATROUS : 0u);
                context.Dispatch(chain.atrous[k][toTransient], c, w, h);
            }
            c.gAtrousStep = 0;
            c.gFlags = 0;
        }
    }

private:
    RelaxSettings m_Settings = {};
    ResourceRef m_Tiles = {};
    uint32_t m_Classify = 0;
    Chain m_Chains[2] = {};
    uint32_t m_ChainNum = 0;
};

} // namespace

std::unique_ptr<MethodBase> CreateRelax(MethodBuilder& builder, Method method)
{
    return std::unique_ptr<MethodBase>(new Relax(builder, method));
}

} // namespace nrd
