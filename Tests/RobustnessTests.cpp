// Robustness matrix (label "robustness"): every method nrd::GetLibraryDesc() lists, fed
// out-of-contract inputs, odd sizes, broken frame sequences and settings at their documented
// limits, on lavapipe under VK_LAYER_KHRONOS_validation. For each case:
//   - no NaN / Inf in any output or float pool texture (all read back after every frame;
//     transient textures are poisoned with NaN between frames, so reads of stale data show);
//   - no validation message;
//   - once the disturbance stops, the error against the known truth is within 1.5x of a clean
//     run's error (same size, same frames since history start, same noise) after the method's
//     documented number of frames (README.md, "Out-of-contract inputs"; MethodTraits below);
//   - where the README documents a behaviour (sky is not written, NaN motion is no motion,
//     out-of-range settings are rejected), that is what happens.
// The inputs a method reads are discovered from its dispatches (IN_* / OUT_* resources), so a new
// method is covered as soon as the library lists it (with the generic cases; its settings limits
// and recovery frames go into TraitsOf). One test per method and case, named "<METHOD> / <case>":
// `nrd_robustness_tests "[SIGMA_SHADOW]"` runs one method. NRD_ROBUSTNESS_VERBOSE=1 prints the
// error of every frame; NRD_ROBUSTNESS_RECOVERY_FRAMES=n lengthens every recovery (to measure one).
#define CATCH_CONFIG_EXTERNAL_INTERFACES // TestEventListenerBase, to release Vulkan before exit.
#include <catch2/catch.hpp>

#include "VulkanTestUtils.h"

#include "RHIVulkan.h"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <limits>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

using namespace nrd;

namespace
{

//==================================================================================================
// The synthetic scene: a plane facing the camera at a known depth, a shadow edge with a linear
// penumbra (known mean visibility), 1-sample-per-pixel binary noise, a strip of sky at the top.
//==================================================================================================

constexpr Identifier kId = 1;
constexpr uint16_t kSize = 48;       // Creation size of most cases.
constexpr float kPlaneViewZ = 10.0f; // In front of the camera; normals face it.
constexpr float kSkyViewZ = 1.0e6f;  // Beyond the default denoisingRange (500000).
constexpr float kPenumbraOverViewZ = 0.25f;
constexpr uint32_t kWarmFrames = 6;  // Clean frames before the disturbance.
constexpr uint32_t kBadFrames = 2;   // Frames with the out-of-contract input.
constexpr uint32_t kSettingsFrames = 4;
constexpr uint32_t kBaselineFrames = 24; // At least; longer when a case needs it.
constexpr double kRecoveryFactor = 1.5;
constexpr double kRecoveryTolerance = 2e-3; // Absolute, for errors close to zero.
const float kNaN = std::numeric_limits<float>::quiet_NaN();
const float kInf = std::numeric_limits<float>::infinity();
// Poison of transient textures between frames: quiet NaNs with payloads no arithmetic produces.
constexpr uint32_t kPoison32 = 0x7fc0beefu;
constexpr uint16_t kPoison16 = 0x7e5au;
constexpr uint32_t kPoison16AsFloat = 0x7f800000u | (uint32_t(kPoison16 & 0x3ffu) << 13); // As read back.

uint32_t Hash(uint32_t x)
{
    x ^= x >> 16;
    x *= 0x7feb352du;
    x ^= x >> 15;
    x *= 0x846ca68bu;
    x ^= x >> 16;
    return x;
}

float Random01(uint32_t seed, uint32_t x, uint32_t y)
{
    return float(Hash(Hash(seed * 0x9e3779b9u + 17u) ^ (x * 0x85ebca6bu) ^ (y * 0xc2b2ae35u)) >> 8) / 16777216.0f;
}

// Lit on the left, shadowed on the right, a linear penumbra over the middle half.
float MeanVisibility(uint32_t x, uint32_t width)
{
    float u = (float(x) + 0.5f) / float(width);
    return std::min(std::max((0.75f - u) * 2.0f, 0.0f), 1.0f);
}

bool IsSkyRow(uint32_t y, uint32_t height)
{
    return height >= 16 && y < 3;
}

float Visibility(uint32_t seed, uint32_t x, uint32_t y, uint32_t width)
{
    return Random01(seed, x, y) < MeanVisibility(x, width) ? 1.0f : 0.0f;
}

// Radiance (REFERENCE) is the visibility times a colour.
const float kRadianceColor[4] = {1.0f, 0.5f, 0.25f, 1.0f};

// Pixels an input case corrupts: a 12x12 block in the penumbra plus every 10th pixel at random.
bool InBadRegion(uint32_t x, uint32_t y, uint32_t width, uint32_t height, bool wholeImage)
{
    if (wholeImage)
        return true;
    int dx = int(x) - int(width / 2), dy = int(y) - int(height / 2);
    return (dx >= -6 && dx < 6 && dy >= -6 && dy < 6) || Hash(x * 7919u + y * 104729u) % 10 == 0;
}

bool StartsWith(const char* s, const char* prefix)
{
    return std::strncmp(s, prefix, std::strlen(prefix)) == 0;
}

bool IsOutput(ResourceType type)
{
    return StartsWith(GetResourceTypeString(type), "OUT_");
}

//==================================================================================================
// Cases.
//==================================================================================================

// What an input case corrupts, by input role.
enum Target : uint32_t
{
    SIGNAL = 1 << 0,    // IN_RADIANCE, IN_SHADOWDATA (.x and .y), IN_SHADOW_TRANSLUCENCY, IN_SHADOW_VISIBILITY,
                        // IN_*_RADIANCE_HITDIST (radiance and hit distance), IN_*_HITDIST, IN_GRADIENTS
    VIEWZ = 1 << 1,     // IN_VIEWZ
    NORMAL = 1 << 2,    // IN_NORMAL_ROUGHNESS.xyz (encoded)
    ROUGHNESS = 1 << 3, // IN_NORMAL_ROUGHNESS.w
    MV = 1 << 4,        // IN_MV .xyz
    CONFIDENCE = 1 << 5, // IN_DIFF_CONFIDENCE, IN_SPEC_CONFIDENCE
};

uint32_t TargetsOf(ResourceType type)
{
    switch (type)
    {
    case ResourceType::IN_RADIANCE:
    case ResourceType::IN_SHADOWDATA:
    case ResourceType::IN_SHADOW_TRANSLUCENCY:
    case ResourceType::IN_SHADOW_VISIBILITY:
    case ResourceType::IN_DIFF_RADIANCE_HITDIST:
    case ResourceType::IN_SPEC_RADIANCE_HITDIST:
    case ResourceType::IN_DIFF_HITDIST:
    case ResourceType::IN_SPEC_HITDIST:
    case ResourceType::IN_GRADIENTS: return SIGNAL;
    case ResourceType::IN_DIFF_CONFIDENCE:
    case ResourceType::IN_SPEC_CONFIDENCE: return CONFIDENCE;
    case ResourceType::IN_VIEWZ: return VIEWZ;
    case ResourceType::IN_NORMAL_ROUGHNESS: return NORMAL | ROUGHNESS;
    case ResourceType::IN_MV: return MV;
    default: return 0;
    }
}

// Method settings, applied through the Integration (tests) or a bare core denoiser (discovery).
struct SettingsCall
{
    std::function<Result(Integration&)> integration;
    std::function<Result(Denoiser&)> core;
    explicit operator bool() const { return bool(integration); }
};

// One frame of a case's sequence.
struct FramePlan
{
    bool bad = false;        // The case's input / settings edits apply.
    bool disturbance = false; // Recovery is measured from the last bad or disturbance frame.
    uint32_t frameIndex = 0;
    AccumulationMode mode = AccumulationMode::CONTINUE;
    uint16_t width = kSize;  // Creation size; a change calls Integration::Resize.
    uint16_t height = kSize;
    uint16_t resourceWidth = 0; // CommonSettings::resourceSize (0: the creation size).
    uint16_t resourceHeight = 0;
    bool sameInputs = false;    // The previous frame's noise again (the same frame submitted twice).
    bool skipCommonSettings = false; // Denoise again without a new SetCommonSettings.
};

struct Case
{
    std::string name;
    std::string tag;            // Catch tag: input, fp16, size, sequence, settings.
    uint32_t targets = 0;       // Inputs the bad frames corrupt (the case applies if the method reads one).
    std::function<void(float* rgba)> edit; // Applied to the targeted channels of bad pixels.
    bool wholeImage = false;
    bool badIsSky = false;      // Documented: bad pixels are sky, not written during the bad frames.
    bool badIsIgnored = false;  // Documented: ignored; the error stays within 1.5x during the bad frames.
    rhi::Format outputFormat = rhi::Format::RGBA32_SFLOAT;
    std::function<void(CommonSettings&)> editCommon; // On bad frames.
    SettingsCall applyBad;                           // Method settings on bad frames (must succeed).
    std::vector<SettingsCall> rejected;              // Must return INVALID_ARGUMENT.
    std::vector<std::function<void(CommonSettings&)>> rejectedCommon;
    std::function<std::vector<FramePlan>(uint32_t recoveryFrames)> plan; // Default: warm, bad, recover.
    uint16_t width = kSize;     // Creation size of the default plan.
    uint16_t height = kSize;
    bool needsBoundedOutputs = false; // Only for methods whose outputs are bounded (not OUT_RADIANCE).
    // Sub-pixel motion on every frame: 1: IN_MV = -0.37, -0.41 pixel (the previous position lies up
    // and to the left, so the first rows below the sky and the first columns resample the sky's and
    // the border's history texels); -1: the opposite (towards the right and bottom edges, and the
    // texels beyond a dynamic resolution's region); 0: none.
    int subPixelMotion = 0;
    // If not 0: the case runs twice, once as planned and once with every byte of the permanent pool
    // set to this pattern before the second frame, which restarts the history (frameIndex 0): what
    // the first frame left, or the memory an application's RHI did not clear. That run also sets the
    // transient pool and the outputs to the pattern before every frame, and the inputs' texels beyond
    // a dynamic resolution's region to NaN (Rig::FillTransientsAndOutputs, UploadInput). The outputs
    // must be the same bit for bit on every frame, and none beyond the region written.
    uint8_t permanentPoolFill = 0;
    // If set: the case runs twice, once as planned and once with the sky pixels' other inputs set to
    // garbage (signals, normals, roughness, confidence: what an engine leaves where nothing was
    // traced), finite or NaN; the outputs must be the same bit for bit on every frame.
    bool skyInputsGarbage = false;
    bool skyInputsNaN = false;
    // If not 0: the case runs twice, the second time with the world's origin this far from the
    // camera on every axis (the camera matrices translated; the camera stays still): the outputs
    // must be the same bit for bit (the passes' world space is camera-relative).
    float worldOriginVariant = 0.0f;
    // If set: method settings given before every frame, by frames since the history started (the
    // pools cases of MethodTraits::poolVariants: a moving light, checkerboard, confidence inputs).
    std::function<SettingsCall(uint32_t frame)> frameSettings;
};

// Documented recovery (README.md, "Out-of-contract inputs"): frames after the last disturbance
// until the error is back within 1.5x of a clean run; methods that accumulate without bound
// (REFERENCE) recover by the application's restart (accumulationMode RESTART on the next frame).
struct MethodTraits
{
    uint32_t recoveryFrames = 32;
    uint32_t smallImageRecoveryFrames = 0; // If not 0: images with a side under 8 pixels.
    bool recoversByRestart = false;
    SettingsCall applyDefaults;                      // Default settings of the method.
    std::vector<SettingsCall> discoveryVariants;     // Settings that change which inputs are read.
    std::vector<Case> settingsCases;                 // At the documented limits.
    // Settings under which the pools cases (tag pools) run again: the paths that the defaults leave
    // alone (Case::frameSettings).
    std::vector<std::pair<std::string, std::function<SettingsCall(uint32_t frame)>>> poolVariants;
    // Another method whose dispatches include every dispatch of this one (same passes, same
    // shaders): its cases stand for this method's, which are not registered again (CI time).
    Method coveredBy = Method::MAX_NUM;
};

template <class T>
SettingsCall Apply(T settings)
{
    SettingsCall call;
    call.integration = [settings](Integration& integration) { return integration.SetMethodSettings(kId, settings); };
    call.core = [settings](Denoiser& denoiser) { return SetMethodSettings(denoiser, kId, settings); };
    return call;
}

template <class T, class Edit>
SettingsCall Edited(Edit edit)
{
    T settings;
    edit(settings);
    return Apply(settings);
}

// Moving lights of the pools variants (SigmaSettings, TiledShadowSettings), by frame: a sun turning
// 0.004 radian a frame (0.4 of a penumbra radius), a sphere light moving 0.05 units a frame 10 units
// away (0.5 of a penumbra radius).
template <class S>
void TurningSun(uint32_t frame, S& s)
{
    float angle = 0.4f + 0.004f * float(frame);
    s.lightDirection[0] = std::sin(angle);
    s.lightDirection[1] = 1.0f;
    s.lightDirection[2] = std::cos(angle);
    s.tanOfLightAngularRadius = 0.01f;
}

template <class S>
void MovingSphereLight(uint32_t frame, S& s)
{
    s.lightPosition[0] = 1.0f + 0.05f * float(frame);
    s.lightPosition[1] = 10.0f;
    s.lightPosition[2] = -2.0f;
    s.lightRadius = 0.1f;
}

Case SettingsCase(const std::string& name, SettingsCall accepted, std::vector<SettingsCall> rejected)
{
    Case c;
    c.name = "settings: " + name;
    c.tag = "settings";
    c.applyBad = accepted;
    c.rejected = std::move(rejected);
    return c;
}

MethodTraits TraitsOf(Method method)
{
    MethodTraits t;
    switch (method)
    {
    case Method::SIGMA_SHADOW:
    case Method::SIGMA_SHADOW_TRANSLUCENCY:
    {
        typedef SigmaSettings S;
        t.recoveryFrames = 8;
        // Where a pixel's whole neighbourhood mixes lit and shadowed pixels the history clamp does
        // not catch stale history: it fades by N / (N + 1) per frame (N = maxStabilizedFrameNum).
        t.smallImageRecoveryFrames = 32;
        t.applyDefaults = Apply(S{});
        t.settingsCases = {
            SettingsCase("blurRadiusScale 0", Edited<S>([](S& s) { s.blurRadiusScale = 0.0f; }),
                         {Edited<S>([](S& s) { s.blurRadiusScale = -1e-6f; })}),
            SettingsCase("blurRadiusScale max", Edited<S>([](S& s) { s.blurRadiusScale = SIGMA_MAX_BLUR_RADIUS_SCALE; }),
                         {Edited<S>([](S& s) { s.blurRadiusScale = SIGMA_MAX_BLUR_RADIUS_SCALE * 1.001f; }),
                          Edited<S>([](S& s) { s.blurRadiusScale = kNaN; })}),
            SettingsCase("maxStabilizedFrameNum 0", Edited<S>([](S& s) { s.maxStabilizedFrameNum = 0; }), {}),
            SettingsCase("maxStabilizedFrameNum max",
                         Edited<S>([](S& s) { s.maxStabilizedFrameNum = SIGMA_MAX_HISTORY_FRAME_NUM; }),
                         {Edited<S>([](S& s) { s.maxStabilizedFrameNum = SIGMA_MAX_HISTORY_FRAME_NUM + 1; })}),
            SettingsCase("planeDistanceSensitivity min", Edited<S>([](S& s) { s.planeDistanceSensitivity = FLT_MIN; }),
                         {Edited<S>([](S& s) { s.planeDistanceSensitivity = 0.0f; })}),
            SettingsCase("planeDistanceSensitivity 1", Edited<S>([](S& s) { s.planeDistanceSensitivity = 1.0f; }),
                         {Edited<S>([](S& s) { s.planeDistanceSensitivity = 1.001f; })}),
            SettingsCase("tanOfLightAngularRadius 1", Edited<S>([](S& s) { s.tanOfLightAngularRadius = 1.0f; s.lightDirection[1] = 1.0f; }),
                         {Edited<S>([](S& s) { s.tanOfLightAngularRadius = 1.001f; }),
                          Edited<S>([](S& s) { s.tanOfLightAngularRadius = -kInf; })}),
            SettingsCase("lightRadius max", Edited<S>([](S& s) { s.lightRadius = 1e6f; s.lightPosition[0] = 1e30f; }),
                         {Edited<S>([](S& s) { s.lightRadius = kNaN; }),
                          Edited<S>([](S& s) { s.lightRadius = 1.0f; s.lightPosition[2] = kInf; })}),
            SettingsCase("lightDirection huge",
                         Edited<S>([](S& s) { s.lightDirection[0] = 1e30f; s.lightDirection[1] = -1e30f; s.lightDirection[2] = 1e30f; }),
                         {Edited<S>([](S& s) { s.lightDirection[2] = kInf; })}),
        };
        t.poolVariants = {{"turning sun", [](uint32_t frame) { return Edited<S>([frame](S& s) { TurningSun(frame, s); }); }},
                          {"moving sphere light", [](uint32_t frame) { return Edited<S>([frame](S& s) { MovingSphereLight(frame, s); }); }}};
        break;
    }
    case Method::REFERENCE:
    {
        typedef ReferenceSettings S;
        t.recoveryFrames = 1;
        t.recoversByRestart = true;
        t.applyDefaults = Apply(S{});
        t.settingsCases = {
            SettingsCase("maxAccumulatedFrameNum 1", Edited<S>([](S& s) { s.maxAccumulatedFrameNum = 1; }),
                         {Edited<S>([](S& s) { s.maxAccumulatedFrameNum = 0; })}),
            SettingsCase("maxAccumulatedFrameNum max",
                         Edited<S>([](S& s) { s.maxAccumulatedFrameNum = REFERENCE_MAX_HISTORY_FRAME_NUM; }),
                         {Edited<S>([](S& s) { s.maxAccumulatedFrameNum = REFERENCE_MAX_HISTORY_FRAME_NUM + 1; })}),
        };
        break;
    }
    case Method::TILED_SHADOW:
    {
        typedef TiledShadowSettings S;
        // Measured: 8 to 10 frames (history that contradicts the signal restarts, a changing
        // neighbourhood keeps at most 4 frames); documented with a margin.
        t.recoveryFrames = 12;
        t.smallImageRecoveryFrames = 16;
        t.applyDefaults = Apply(S{});
        t.discoveryVariants = {Edited<S>([](S& s) { s.isBitmaskInput = true; }),
                               Edited<S>([](S& s) { s.isShadowDataInput = true; })};
        t.settingsCases = {
            SettingsCase("isBitmaskInput", Edited<S>([](S& s) { s.isBitmaskInput = true; }), {}),
            SettingsCase("isShadowDataInput, sphere light",
                         Edited<S>([](S& s) { s.isShadowDataInput = true; s.lightRadius = 1e6f; s.lightPosition[0] = 1e30f; }),
                         {Edited<S>([](S& s) { s.isShadowDataInput = true; s.lightRadius = 1e6f * 1.001f; }),
                          Edited<S>([](S& s) { s.lightPosition[1] = kNaN; })}),
            SettingsCase("isShadowDataInput, infinite light",
                         Edited<S>([](S& s) { s.isShadowDataInput = true; s.tanOfLightAngularRadius = 1.0f; s.lightDirection[1] = 1.0f; }),
                         {Edited<S>([](S& s) { s.tanOfLightAngularRadius = -1e-6f; }),
                          Edited<S>([](S& s) { s.lightDirection[2] = kInf; })}),
            SettingsCase("enableTileSkipping off", Edited<S>([](S& s) { s.enableTileSkipping = false; }), {}),
            SettingsCase("neighborhoodRadius 1", Edited<S>([](S& s) { s.neighborhoodRadius = 1; }),
                         {Edited<S>([](S& s) { s.neighborhoodRadius = 0; })}),
            SettingsCase("neighborhoodRadius max",
                         Edited<S>([](S& s) { s.neighborhoodRadius = TILED_SHADOW_MAX_NEIGHBORHOOD_RADIUS; }),
                         {Edited<S>([](S& s) { s.neighborhoodRadius = TILED_SHADOW_MAX_NEIGHBORHOOD_RADIUS + 1; })}),
            SettingsCase("historyClampSigma min", Edited<S>([](S& s) { s.historyClampSigma = FLT_MIN; }),
                         {Edited<S>([](S& s) { s.historyClampSigma = 0.0f; })}),
            SettingsCase("historyClampSigma max", Edited<S>([](S& s) { s.historyClampSigma = 8.0f; }),
                         {Edited<S>([](S& s) { s.historyClampSigma = 8.001f; }),
                          Edited<S>([](S& s) { s.historyClampSigma = kNaN; })}),
            SettingsCase("disocclusionThresholdGrazing 1", Edited<S>([](S& s) { s.disocclusionThresholdGrazing = 1.0f; }),
                         {Edited<S>([](S& s) { s.disocclusionThresholdGrazing = 1.001f; })}),
            SettingsCase("planeDistanceSensitivity min", Edited<S>([](S& s) { s.planeDistanceSensitivity = FLT_MIN; }),
                         {Edited<S>([](S& s) { s.planeDistanceSensitivity = 0.0f; })}),
            SettingsCase("normalPower 0", Edited<S>([](S& s) { s.normalPower = 0.0f; }),
                         {Edited<S>([](S& s) { s.normalPower = -1e-6f; })}),
            SettingsCase("normalPower max", Edited<S>([](S& s) { s.normalPower = 128.0f; }),
                         {Edited<S>([](S& s) { s.normalPower = 128.01f; })}),
            SettingsCase("atrousPassNum 1", Edited<S>([](S& s) { s.atrousPassNum = 1; }),
                         {Edited<S>([](S& s) { s.atrousPassNum = 0; })}),
            SettingsCase("atrousPassNum max", Edited<S>([](S& s) { s.atrousPassNum = 3; }),
                         {Edited<S>([](S& s) { s.atrousPassNum = 4; })}),
            SettingsCase("maxHistoryFrameNum 1", Edited<S>([](S& s) { s.maxHistoryFrameNum = 1; }),
                         {Edited<S>([](S& s) { s.maxHistoryFrameNum = 0; })}),
            SettingsCase("maxHistoryFrameNum max",
                         Edited<S>([](S& s) { s.maxHistoryFrameNum = TILED_SHADOW_MAX_HISTORY_FRAME_NUM; }),
                         {Edited<S>([](S& s) { s.maxHistoryFrameNum = TILED_SHADOW_MAX_HISTORY_FRAME_NUM + 1; })}),
        };
        for (uint8_t view = 1; view < uint8_t(TiledShadowDebug::MAX_NUM); view++)
            t.settingsCases.push_back(SettingsCase("debugView " + std::to_string(view),
                                                   Edited<S>([view](S& s) { s.debugView = TiledShadowDebug(view); }),
                                                   {Edited<S>([](S& s) { s.debugView = TiledShadowDebug::MAX_NUM; })}));
        t.poolVariants = {{"shadow data, turning sun",
                           [](uint32_t frame) {
                               return Edited<S>([frame](S& s) {
                                   s.isShadowDataInput = true;
                                   TurningSun(frame, s);
                               });
                           }},
                          {"bitmask input", [](uint32_t) { return Edited<S>([](S& s) { s.isBitmaskInput = true; }); }}};
        break;
    }
    case Method::REBLUR_DIFFUSE:
    case Method::REBLUR_SPECULAR:
    case Method::REBLUR_DIFFUSE_SPECULAR:
    case Method::REBLUR_DIFFUSE_OCCLUSION:
    case Method::REBLUR_SPECULAR_OCCLUSION:
    case Method::REBLUR_DIFFUSE_SPECULAR_OCCLUSION:
    {
        typedef ReblurSettings S;
        // The single-signal methods run a subset of their pair's dispatches (Source/Reblur.cpp).
        if (method == Method::REBLUR_DIFFUSE || method == Method::REBLUR_SPECULAR)
            t.coveredBy = Method::REBLUR_DIFFUSE_SPECULAR;
        if (method == Method::REBLUR_DIFFUSE_OCCLUSION || method == Method::REBLUR_SPECULAR_OCCLUSION)
            t.coveredBy = Method::REBLUR_DIFFUSE_SPECULAR_OCCLUSION;
        t.applyDefaults = Apply(S{});
        t.discoveryVariants = {Edited<S>([](S& s) { s.isConfidenceInput = true; })};
        t.settingsCases = {
            SettingsCase("maxAccumulatedFrameNum 0", Edited<S>([](S& s) { s.maxAccumulatedFrameNum = 0; s.maxFastAccumulatedFrameNum = 0; }),
                         {Edited<S>([](S& s) { s.maxAccumulatedFrameNum = REBLUR_MAX_HISTORY_FRAME_NUM + 1; })}),
            SettingsCase("blurRadius max, pre-pass max",
                         Edited<S>([](S& s) { s.blurRadius = REBLUR_MAX_BLUR_RADIUS; s.diffusePrePassBlurRadius = s.specularPrePassBlurRadius = s.occlusionPrePassBlurRadius = REBLUR_MAX_BLUR_RADIUS; }),
                         {Edited<S>([](S& s) { s.specularPrePassBlurRadius = kNaN; })}),
            SettingsCase("forceReferenceAccumulation", Edited<S>([](S& s) { s.forceReferenceAccumulation = true; }), {}),
            SettingsCase("checkerboard", Edited<S>([](S& s) { s.checkerboardMode = CheckerboardMode::BLACK; }),
                         {Edited<S>([](S& s) { s.checkerboardMode = CheckerboardMode(3); })}),
            SettingsCase("colour compression and anti-firefly max",
                         Edited<S>([](S& s) { s.colorCompression = 16.0f; s.antiFireflySigma = 64.0f; }),
                         {Edited<S>([](S& s) { s.colorCompression = 16.5f; })}),
        };
        t.poolVariants = {{"checkerboard", [](uint32_t) { return Edited<S>([](S& s) { s.checkerboardMode = CheckerboardMode::BLACK; }); }},
                          {"confidence input", [](uint32_t) { return Edited<S>([](S& s) { s.isConfidenceInput = true; }); }}};
        break;
    }
    case Method::CONFIDENCE:
    {
        typedef ConfidenceSettings S;
        // After bad gradients the confidence rises back by riseHistoryWeight per frame.
        t.recoveryFrames = 16;
        t.applyDefaults = Apply(S{});
        t.settingsCases = {
            SettingsCase("gradientThreshold max", Edited<S>([](S& s) { s.gradientThreshold = 0.999f; }),
                         {Edited<S>([](S& s) { s.gradientThreshold = 1.0f; }),
                          Edited<S>([](S& s) { s.gradientThreshold = -1e-6f; })}),
            SettingsCase("gradientSensitivity max", Edited<S>([](S& s) { s.gradientSensitivity = 1000.0f; s.specularGradientSensitivity = 1000.0f; }),
                         {Edited<S>([](S& s) { s.gradientSensitivity = 0.999f; }),
                          Edited<S>([](S& s) { s.gradientSensitivity = kNaN; }),
                          Edited<S>([](S& s) { s.specularGradientSensitivity = 0.999f; })}),
            SettingsCase("history weights 0", Edited<S>([](S& s) { s.fallHistoryWeight = 0.0f; s.riseHistoryWeight = 0.0f; }),
                         {Edited<S>([](S& s) { s.fallHistoryWeight = 1.0f; }),
                          Edited<S>([](S& s) { s.riseHistoryWeight = -1e-6f; })}),
            SettingsCase("atrousPassNum 1", Edited<S>([](S& s) { s.atrousPassNum = 1; }),
                         {Edited<S>([](S& s) { s.atrousPassNum = 0; })}),
            SettingsCase("localGradientRadius max", Edited<S>([](S& s) { s.localGradientRadius = CONFIDENCE_MAX_LOCAL_GRADIENT_RADIUS; }),
                         {Edited<S>([](S& s) { s.localGradientRadius = CONFIDENCE_MAX_LOCAL_GRADIENT_RADIUS + 1; })}),
            SettingsCase("atrousPassNum max, edge stopping off",
                         Edited<S>([](S& s) { s.atrousPassNum = CONFIDENCE_MAX_ATROUS_PASS_NUM; s.depthThreshold = 0.0f; s.normalPower = 0.0f; }),
                         {Edited<S>([](S& s) { s.atrousPassNum = CONFIDENCE_MAX_ATROUS_PASS_NUM + 1; }),
                          Edited<S>([](S& s) { s.normalPower = 128.5f; }),
                          Edited<S>([](S& s) { s.depthThreshold = kInf; })}),
        };
        break;
    }
    case Method::REFLECTION:
    {
        typedef ReflectionSettings S;
        t.applyDefaults = Apply(S{});
        t.settingsCases = {
            SettingsCase("raysPerQuad 4, no guided tracing",
                         Edited<S>([](S& s) { s.raysPerQuad = 4; s.enableTemporalVarianceGuidedTracing = false; }),
                         {Edited<S>([](S& s) { s.raysPerQuad = 3; })}),
            SettingsCase("roughnessThreshold 0, mirrorRoughness 1",
                         Edited<S>([](S& s) { s.roughnessThreshold = 0.0f; s.mirrorRoughness = 1.0f; }),
                         {Edited<S>([](S& s) { s.roughnessThreshold = kNaN; })}),
            SettingsCase("maxHistoryFrameNum 1, no spatial, no blur",
                         Edited<S>([](S& s) { s.maxHistoryFrameNum = 1; s.enableSpatial = false; s.enableBlur = false; }),
                         {Edited<S>([](S& s) { s.maxHistoryFrameNum = 0; })}),
            SettingsCase("edge stops at their limits",
                         Edited<S>([](S& s) { s.normalSigma = 4096.0f; s.depthSigma = 64.0f; s.historyClipSigma = 16.0f; s.historyClipLeeway = 4.0f; }),
                         {Edited<S>([](S& s) { s.normalSigma = 4097.0f; })}),
        };
        break;
    }
    case Method::RELAX_DIFFUSE:
    case Method::RELAX_SPECULAR:
    case Method::RELAX_DIFFUSE_SPECULAR:
    {
        typedef RelaxSettings S;
        // The single-signal methods run one of their pair's two chains (Source/Relax.cpp).
        if (method != Method::RELAX_DIFFUSE_SPECULAR)
            t.coveredBy = Method::RELAX_DIFFUSE_SPECULAR;
        // Measured: 11 to 13 frames after out-of-range values (the fast history is clamped to the
        // input, the slow one to the fast one), 20 after a whole image of zero or NaN (the fast
        // history drops to 0 with the input and climbs back at its own rate); documented with a margin.
        t.recoveryFrames = 24;
        t.applyDefaults = Apply(S{});
        t.discoveryVariants = {Edited<S>([](S& s) { s.useConfidenceInputs = true; })};
        t.poolVariants = {{"checkerboard, confidence inputs", [](uint32_t) {
                               return Edited<S>([](S& s) {
                                   s.checkerboardMode = CheckerboardMode::WHITE;
                                   s.useConfidenceInputs = true;
                               });
                           }}};
        t.settingsCases = {
            SettingsCase("no accumulation",
                         Edited<S>([](S& s) {
                             s.diffuseMaxAccumulatedFrameNum = s.specularMaxAccumulatedFrameNum = 0;
                             s.diffuseMaxFastAccumulatedFrameNum = s.specularMaxFastAccumulatedFrameNum = 0;
                         }),
                         {Edited<S>([](S& s) { s.diffuseMaxFastAccumulatedFrameNum = s.diffuseMaxAccumulatedFrameNum + 1; }),
                          Edited<S>([](S& s) { s.specularMaxAccumulatedFrameNum = RELAX_MAX_HISTORY_FRAME_NUM + 1; })}),
            SettingsCase("checkerboard, confidence inputs",
                         Edited<S>([](S& s) { s.checkerboardMode = CheckerboardMode::WHITE; s.useConfidenceInputs = true; }),
                         {Edited<S>([](S& s) { s.checkerboardMode = CheckerboardMode(3); })}),
            SettingsCase("atrousIterationNum 2", Edited<S>([](S& s) { s.atrousIterationNum = 2; }),
                         {Edited<S>([](S& s) { s.atrousIterationNum = 1; })}),
            SettingsCase("atrousIterationNum 8, history fix off, anti-firefly on",
                         Edited<S>([](S& s) { s.atrousIterationNum = 8; s.historyFixFrameNum = 0; s.enableAntiFirefly = true; }),
                         {Edited<S>([](S& s) { s.atrousIterationNum = 9; }), Edited<S>([](S& s) { s.historyFixFrameNum = 4; })}),
            SettingsCase("stoppers and anti-lag at their limits",
                         Edited<S>([](S& s) {
                             s.diffusePhiLuminance = s.specularPhiLuminance = 16.0f;
                             s.depthThreshold = s.roughnessFraction = 1.0f;
                             s.specularLobeAngleSlack = 90.0f;
                             s.antilagSigmaScale = 16.0f;
                         }),
                         {Edited<S>([](S& s) { s.depthThreshold = kNaN; }),
                          Edited<S>([](S& s) { s.hitDistanceParameters.A = 0.0f; })}),
        };
        break;
    }
    default:
        // A method without an entry here still runs every generic case, with the defaults above.
        break;
    }
    // NRD_ROBUSTNESS_RECOVERY_FRAMES=n runs longer recoveries (to measure them with NRD_ROBUSTNESS_VERBOSE=1).
    if (const char* frames = std::getenv("NRD_ROBUSTNESS_RECOVERY_FRAMES"))
    {
        t.recoveryFrames = std::max<uint32_t>(t.recoveryFrames, uint32_t(std::atoi(frames)));
        t.smallImageRecoveryFrames = std::max<uint32_t>(t.smallImageRecoveryFrames, t.recoveryFrames);
    }
    return t;
}

Case InputCase(const std::string& name, uint32_t targets, std::function<void(float*)> edit)
{
    Case c;
    c.name = name;
    c.tag = "input";
    c.targets = targets;
    c.edit = std::move(edit);
    return c;
}

Case SequenceCase(const std::string& name, std::function<std::vector<FramePlan>(uint32_t)> plan)
{
    Case c;
    c.name = name;
    c.tag = "sequence";
    c.plan = std::move(plan);
    return c;
}

// Frames numbered from 0 (a restart), the disturbance at 'kWarmFrames'.
std::vector<FramePlan> CleanFrames(uint32_t num)
{
    std::vector<FramePlan> frames(num);
    for (uint32_t i = 0; i < num; i++)
        frames[i].frameIndex = i;
    return frames;
}

void Append(std::vector<FramePlan>& plan, uint32_t num, FramePlan model)
{
    for (uint32_t i = 0; i < num; i++)
    {
        FramePlan f = model;
        f.frameIndex = plan.empty() ? 0 : plan.back().frameIndex + 1;
        plan.push_back(f);
    }
}

std::vector<Case> GenericCases()
{
    std::vector<Case> cases;
    auto all = [](float v) { return [v](float* p) { p[0] = p[1] = p[2] = p[3] = v; }; };

    // Signals (radiance, shadow data, translucency, visibility): every channel.
    const std::pair<const char*, float> signals[] = {
        {"NaN", kNaN},       {"+Inf", kInf},         {"-Inf", -kInf},           {"negative", -1.0f},
        {"-1e30", -1e30f},   {"1e30", 1e30f},        {"denormal", 1e-40f},      {"above fp16 max", 65520.0f},
        {"fp16 max", 65504.0f}};
    for (const auto& s : signals)
        cases.push_back(InputCase(std::string("signal ") + s.first, SIGNAL, all(s.second)));
    Case zero = InputCase("signal all zero", SIGNAL, all(0.0f));
    zero.wholeImage = true;
    cases.push_back(zero);
    Case nanEverywhere = InputCase("signal NaN everywhere", SIGNAL, all(kNaN));
    nanEverywhere.wholeImage = true;
    cases.push_back(nanEverywhere);

    // Confidence (history validity in [0, 1]): out-of-contract values, and history invalid everywhere.
    const std::pair<const char*, float> confidences[] = {
        {"NaN", kNaN}, {"+Inf", kInf}, {"-Inf", -kInf}, {"negative", -1.0f}, {"above 1", 3.0f}, {"denormal", 1e-40f}};
    for (const auto& s : confidences)
        cases.push_back(InputCase(std::string("confidence ") + s.first, CONFIDENCE, all(s.second)));
    Case invalidHistory = InputCase("confidence 0 everywhere (history invalid)", CONFIDENCE, all(0.0f));
    invalidHistory.wholeImage = true;
    cases.push_back(invalidHistory);

    // FP16 outputs: values above 65504 must not turn into Inf on the way out.
    for (const auto& s : {std::make_pair("fp16 outputs: signal above fp16 max", 65520.0f),
                          std::make_pair("fp16 outputs: signal 1e30", 1e30f), std::make_pair("fp16 outputs: signal +Inf", kInf)})
    {
        Case c = InputCase(s.first, SIGNAL, all(s.second));
        c.tag = "fp16";
        c.outputFormat = rhi::Format::RGBA16_SFLOAT;
        c.needsBoundedOutputs = true; // OUT_RADIANCE is the mean of its inputs: use RGBA32F above 65504.
        cases.push_back(c);
    }
    Case fp16Edge = InputCase("fp16 outputs: signal 60000", SIGNAL, all(60000.0f));
    fp16Edge.tag = "fp16";
    fp16Edge.outputFormat = rhi::Format::RGBA16_SFLOAT;
    cases.push_back(fp16Edge);
    Case fp16Clean = SequenceCase("fp16 outputs: clean", nullptr);
    fp16Clean.tag = "fp16";
    fp16Clean.outputFormat = rhi::Format::RGBA16_SFLOAT;
    cases.push_back(fp16Clean);

    // viewZ: non-positive, non-finite and beyond denoisingRange are sky (not written); tiny is valid.
    const std::pair<const char*, float> depths[] = {{"0", 0.0f},          {"-0", -0.0f},       {"negative", -10.0f},
                                                    {"1e7", 1e7f},        {"+Inf", kInf},      {"-Inf", -kInf},
                                                    {"NaN", kNaN},        {"beyond denoisingRange", 500001.0f}};
    for (const auto& d : depths)
    {
        Case c = InputCase(std::string("viewZ ") + d.first, VIEWZ, all(d.second));
        c.badIsSky = true;
        cases.push_back(c);
    }
    cases.push_back(InputCase("viewZ 1e-6", VIEWZ, all(1e-6f)));
    cases.push_back(InputCase("viewZ 1e-30", VIEWZ, all(1e-30f)));
    cases.push_back(InputCase("viewZ denormal", VIEWZ, all(1e-40f)));

    // Normals (encoded n * 0.5 + 0.5) and roughness.
    cases.push_back(InputCase("normal zero length", NORMAL, [](float* p) { p[0] = p[1] = p[2] = 0.5f; }));
    cases.push_back(InputCase("normal non-unit", NORMAL, [](float* p) { p[0] = 1.0f; p[1] = 1.0f; p[2] = 0.25f; }));
    cases.push_back(InputCase("normal huge", NORMAL, [](float* p) { p[0] = 1e30f; p[1] = -1e30f; p[2] = 1e30f; }));
    cases.push_back(InputCase("normal NaN", NORMAL, [](float* p) { p[0] = p[1] = p[2] = kNaN; }));
    cases.push_back(InputCase("normal Inf", NORMAL, [](float* p) { p[0] = kInf; p[1] = -kInf; }));
    for (float r : {-1.0f, 0.0f, 1.0f, 2.0f})
    {
        char name[64];
        std::snprintf(name, sizeof(name), "roughness %g", double(r));
        cases.push_back(InputCase(name, ROUGHNESS, [r](float* p) { p[3] = r; }));
    }
    cases.push_back(InputCase("roughness NaN", ROUGHNESS, [](float* p) { p[3] = kNaN; }));

    // Motion: off screen and huge disocclude; NaN is no motion.
    cases.push_back(InputCase("motion far off screen", MV, [](float* p) { p[0] = 10.0f; p[1] = -7.0f; }));
    cases.push_back(InputCase("motion huge", MV, [](float* p) { p[0] = 1e30f; p[1] = -1e30f; p[2] = 1e30f; }));
    Case mvInf = InputCase("motion +-Inf", MV, [](float* p) { p[0] = kInf; p[1] = -kInf; p[2] = kInf; });
    mvInf.badIsIgnored = true;
    cases.push_back(mvInf);
    Case mvNaN = InputCase("motion NaN", MV, [](float* p) { p[0] = p[1] = p[2] = kNaN; });
    mvNaN.badIsIgnored = true;
    cases.push_back(mvNaN);
    Case worldMv = InputCase("world-space motion huge", MV, [](float* p) { p[0] = 1e30f; p[1] = 1e30f; p[2] = -1e30f; });
    worldMv.editCommon = [](CommonSettings& s) { s.isMotionVectorInWorldSpace = true; };
    cases.push_back(worldMv);

    // Sizes: NaN signal at that creation size, compared with a clean run at the same size.
    const std::pair<uint16_t, uint16_t> sizes[] = {{1, 1}, {2, 2}, {7, 5}, {33, 17}, {4097, 3}};
    for (const auto& s : sizes)
    {
        Case c = InputCase("size " + std::to_string(s.first) + "x" + std::to_string(s.second) + " with NaN signal",
                           SIGNAL, all(kNaN));
        c.tag = "size";
        c.width = s.first;
        c.height = s.second;
        cases.push_back(c);
    }

    // Sequences.
    auto disturbedAt = [](uint32_t recovery, std::function<void(FramePlan&)> disturb) {
        std::vector<FramePlan> plan = CleanFrames(kWarmFrames);
        FramePlan model;
        Append(plan, 1, model);
        plan.back().disturbance = true;
        disturb(plan.back());
        Append(plan, recovery + 2, model);
        return plan;
    };
    cases.push_back(SequenceCase("frameIndex reset mid-sequence", [disturbedAt](uint32_t r) {
        std::vector<FramePlan> plan = disturbedAt(r, [](FramePlan& f) { f.frameIndex = 0; });
        for (size_t i = kWarmFrames + 1; i < plan.size(); i++)
            plan[i].frameIndex = plan[i - 1].frameIndex + 1;
        return plan;
    }));
    cases.push_back(SequenceCase("accumulationMode RESTART mid-sequence", [disturbedAt](uint32_t r) {
        return disturbedAt(r, [](FramePlan& f) { f.mode = AccumulationMode::RESTART; });
    }));
    cases.push_back(SequenceCase("skipped frames", [disturbedAt](uint32_t r) {
        std::vector<FramePlan> plan = disturbedAt(r, [](FramePlan& f) { f.frameIndex += 17; });
        for (size_t i = kWarmFrames + 1; i < plan.size(); i++)
            plan[i].frameIndex = plan[i - 1].frameIndex + 1;
        return plan;
    }));
    cases.push_back(SequenceCase("same frame submitted twice", [](uint32_t r) {
        std::vector<FramePlan> plan = CleanFrames(kWarmFrames);
        FramePlan again = plan.back();
        again.disturbance = true;
        again.sameInputs = true;
        plan.push_back(again);
        Append(plan, r + 2, FramePlan());
        return plan;
    }));
    cases.push_back(SequenceCase("Denoise twice for one SetCommonSettings", [](uint32_t r) {
        std::vector<FramePlan> plan = CleanFrames(kWarmFrames);
        FramePlan again = plan.back();
        again.disturbance = true;
        again.sameInputs = true;
        again.skipCommonSettings = true;
        plan.push_back(again);
        Append(plan, r + 2, FramePlan());
        return plan;
    }));
    cases.push_back(SequenceCase("frameIndex wraps around", [](uint32_t r) {
        std::vector<FramePlan> plan = CleanFrames(kWarmFrames + r + 3);
        for (size_t i = 1; i < plan.size(); i++)
            plan[i].frameIndex = 0xffffffffu - uint32_t(kWarmFrames) + uint32_t(i); // 0 (a restart) at kWarmFrames.
        plan[kWarmFrames].disturbance = true;
        return plan;
    }));
    cases.push_back(SequenceCase("resize down then up", [](uint32_t r) {
        std::vector<FramePlan> plan = CleanFrames(kWarmFrames);
        FramePlan small;
        small.width = 32;
        small.height = 24;
        Append(plan, r + 2, small);
        plan[kWarmFrames].disturbance = true;
        size_t up = plan.size();
        Append(plan, r + 2, FramePlan());
        plan[up].disturbance = true;
        return plan;
    }));
    // A restart over a permanent pool of garbage: a frame with frameIndex 0 starts the history, so
    // every texel a later frame reads must have been written since. Finite garbage, then all ones
    // (NaN in every float format). Under sub-pixel 2D motion towards the sky and the border, and
    // under camera motion (world-space motion vectors of a still world, the previous camera 0.3
    // units up and left of this one: 0.72 pixel at 48x48; the path of the plane tests and of
    // specular virtual motion).
    // With a dynamic resolution (resourceSize 40x36 of 48x48 after a first frame at the whole size) the
    // motion is the opposite, towards the region's right and bottom edges: the texels beyond them are
    // not written after the restart either.
    auto poolCase = [](bool camera, uint8_t fill, bool dynamic) {
        std::string name = std::string("restart over a permanent pool of ") + (fill == 0xff ? "all ones (NaN)" : "0x3f bytes") +
                           (camera ? ", camera motion" : ", sub-pixel motion") +
                           (dynamic ? " towards the region's edge, dynamic resolution" : "");
        Case c = SequenceCase(name, [camera, dynamic](uint32_t) {
            std::vector<FramePlan> plan = CleanFrames(1);
            for (const FramePlan& f : CleanFrames(10))
                plan.push_back(f); // frameIndex 0 again: a restart.
            for (size_t t = 0; t < plan.size(); t++)
            {
                plan[t].bad = camera; // The camera edit applies to every frame.
                // The first frame at the whole size, so that the texels beyond the region hold a
                // history of the same surfaces where the pool is not filled.
                plan[t].resourceWidth = dynamic && t > 0 ? 40 : 0;
                plan[t].resourceHeight = dynamic && t > 0 ? 36 : 0;
            }
            return plan;
        });
        c.tag = "pools";
        c.permanentPoolFill = fill;
        c.subPixelMotion = camera ? 0 : dynamic ? -1 : 1;
        float shift = dynamic ? 0.3f : -0.3f;
        if (camera)
            c.editCommon = [shift](CommonSettings& s) {
                s.isMotionVectorInWorldSpace = true;
                s.worldToViewMatrixPrev[12] = shift; // Column-major: the translation column.
                s.worldToViewMatrixPrev[13] = shift;
            };
        return c;
    };
    for (bool camera : {false, true})
    {
        for (uint8_t fill : {uint8_t(0x3f), uint8_t(0xff)})
            cases.push_back(poolCase(camera, fill, false));
        cases.push_back(poolCase(camera, 0xff, true));
    }
    // The sky's inputs hold garbage (finite, NaN) under sub-pixel motion: nothing of them reaches a
    // surface pixel's output (sky taps carry no weight anywhere, also in neighbourhood statistics).
    // The sky pixels' own outputs are left out (a method that does not read viewZ, REFERENCE,
    // accumulates whatever it is given).
    for (bool nan : {false, true})
    {
        Case c = SequenceCase(nan ? "sky inputs NaN, sub-pixel motion" : "sky inputs garbage, sub-pixel motion",
                              [](uint32_t) { return CleanFrames(10); });
        c.tag = "pools";
        c.subPixelMotion = 1;
        c.skyInputsGarbage = true;
        c.skyInputsNaN = nan;
        cases.push_back(c);
    }
    // A world far from the origin (100 km, a large level without origin rebasing): the same outputs,
    // bit for bit, as at the origin, under sub-pixel motion (a still camera: only the origin moves).
    {
        Case c = SequenceCase("a world 1e5 units from the origin, sub-pixel motion", [](uint32_t) { return CleanFrames(10); });
        c.tag = "pools";
        c.subPixelMotion = 1;
        c.worldOriginVariant = 1e5f;
        cases.push_back(c);
    }
    cases.push_back(SequenceCase("dynamic resolution down then up", [](uint32_t r) {
        std::vector<FramePlan> plan = CleanFrames(kWarmFrames);
        FramePlan small;
        small.resourceWidth = 32;
        small.resourceHeight = 24;
        Append(plan, r + 2, small);
        plan[kWarmFrames].disturbance = true;
        size_t up = plan.size();
        Append(plan, r + 2, FramePlan());
        plan[up].disturbance = true;
        return plan;
    }));

    // Common settings at their documented limits, and just beyond (rejected, previous kept).
    auto common = [](const char* name, std::function<void(CommonSettings&)> edit,
                     std::vector<std::function<void(CommonSettings&)>> rejected) {
        Case c;
        c.name = std::string("common settings: ") + name;
        c.tag = "settings";
        c.editCommon = std::move(edit);
        c.rejectedCommon = std::move(rejected);
        return c;
    };
    Case tinyRange = common("denoisingRange min", [](CommonSettings& s) { s.denoisingRange = FLT_MIN; },
                            {[](CommonSettings& s) { s.denoisingRange = 0.0f; }, [](CommonSettings& s) { s.denoisingRange = kInf; }});
    tinyRange.badIsSky = true; // Everything is beyond the range.
    tinyRange.wholeImage = true;
    cases.push_back(tinyRange);
    cases.push_back(common("denoisingRange max", [](CommonSettings& s) { s.denoisingRange = FLT_MAX; },
                           {[](CommonSettings& s) { s.denoisingRange = kNaN; }}));
    cases.push_back(common("disocclusionThreshold min", [](CommonSettings& s) { s.disocclusionThreshold = FLT_MIN; },
                           {[](CommonSettings& s) { s.disocclusionThreshold = 0.0f; }}));
    cases.push_back(common("disocclusionThreshold 1", [](CommonSettings& s) { s.disocclusionThreshold = 1.0f; },
                           {[](CommonSettings& s) { s.disocclusionThreshold = 1.001f; }}));
    cases.push_back(common("jitter +-0.5",
                           [](CommonSettings& s) {
                               s.cameraJitter[0] = 0.5f;
                               s.cameraJitter[1] = -0.5f;
                               s.cameraJitterPrev[0] = -0.5f;
                               s.cameraJitterPrev[1] = 0.5f;
                           },
                           {[](CommonSettings& s) { s.cameraJitter[0] = 0.5001f; }}));
    cases.push_back(common("motionVectorScale 0", [](CommonSettings& s) { s.motionVectorScale[0] = s.motionVectorScale[1] = 0.0f; },
                           {[](CommonSettings& s) { s.motionVectorScale[0] = kNaN; }}));
    cases.push_back(common("motionVectorScale huge",
                           [](CommonSettings& s) { s.motionVectorScale[0] = s.motionVectorScale[1] = s.motionVectorScale[2] = 1e30f; },
                           {[](CommonSettings& s) { s.motionVectorScale[1] = kInf; }}));
    return cases;
}

//==================================================================================================
// The Vulkan side: one context for the run, one Integration per method.
//==================================================================================================

bool IsFloatFormat(rhi::Format format)
{
    switch (format)
    {
    case rhi::Format::R16_SFLOAT:
    case rhi::Format::RG16_SFLOAT:
    case rhi::Format::RGBA16_SFLOAT:
    case rhi::Format::R32_SFLOAT:
    case rhi::Format::RG32_SFLOAT:
    case rhi::Format::RGBA32_SFLOAT:
    case rhi::Format::R11_G11_B10_UFLOAT: return true;
    default: return false;
    }
}

size_t CountNonFinite(const std::vector<float>& values)
{
    size_t n = 0;
    for (float v : values)
        n += !std::isfinite(v);
    return n;
}

// Non-finite values of the pixels a method writes: the region, sky rows left out.
size_t CountNonFiniteWritten(const std::vector<float>& values, uint32_t width, uint32_t regionWidth, uint32_t regionHeight)
{
    size_t n = 0;
    for (uint32_t y = 0; y < regionHeight; y++)
        for (uint32_t x = 0; x < regionWidth && !IsSkyRow(y, regionHeight); x++)
            for (uint32_t ch = 0; ch < 4; ch++)
                n += !std::isfinite(values[(size_t(y) * width + x) * 4 + ch]);
    return n;
}

// "first at (x, y).c = value" for a failure message.
std::string FirstNonFinite(const std::vector<float>& values, uint32_t width, uint32_t channels)
{
    for (size_t i = 0; i < values.size(); i++)
        if (!std::isfinite(values[i]))
        {
            size_t pixel = i / channels;
            std::string text = "first at (" + std::to_string(pixel % width) + ", " + std::to_string(pixel / width) + ") =";
            for (uint32_t c = 0; c < channels; c++)
                text += " " + std::to_string(values[pixel * channels + c]);
            return text;
        }
    return "none";
}

// Inputs and outputs a method's dispatches reference (core only), over a few frames and the
// settings variants that change what is read.
void DiscoverResources(Method method, const MethodTraits& traits, std::vector<ResourceType>& inputs,
                       std::vector<ResourceType>& outputs)
{
    MethodDesc methodDesc = {kId, method};
    DenoiserCreationDesc desc;
    desc.methods = &methodDesc;
    desc.methodsNum = 1;
    desc.renderWidth = kSize;
    desc.renderHeight = kSize;
    bool seen[size_t(ResourceType::MAX_NUM)] = {};
    for (size_t variant = 0; variant <= traits.discoveryVariants.size(); variant++)
    {
        Denoiser* denoiser = nullptr;
        if (CreateDenoiser(desc, denoiser) != Result::SUCCESS)
            return;
        if (variant > 0)
            traits.discoveryVariants[variant - 1].core(*denoiser);
        for (uint32_t frame = 0; frame < 3; frame++)
        {
            CommonSettings settings = test::StillCameraSettings(frame);
            const DispatchDesc* dispatches = nullptr;
            uint32_t num = 0;
            if (SetCommonSettings(*denoiser, settings) != Result::SUCCESS ||
                GetComputeDispatches(*denoiser, nullptr, 0, dispatches, num) != Result::SUCCESS)
                break;
            for (uint32_t d = 0; d < num; d++)
                for (uint32_t r = 0; r < dispatches[d].resourcesNum; r++)
                {
                    ResourceType type = dispatches[d].resources[r].type;
                    if (uint32_t(type) < uint32_t(ResourceType::TRANSIENT_POOL))
                        seen[size_t(type)] = true;
                }
        }
        DestroyDenoiser(denoiser);
    }
    for (uint32_t i = 0; i < uint32_t(ResourceType::TRANSIENT_POOL); i++)
        if (seen[i])
            (IsOutput(ResourceType(i)) ? outputs : inputs).push_back(ResourceType(i));
}

//==================================================================================================
// One method's Integration and application textures, reused by all its cases.
//==================================================================================================

struct FrameRecord
{
    uint16_t width = 0, height = 0;             // Creation size.
    uint16_t regionWidth = 0, regionHeight = 0; // Pixels processed.
    uint32_t framesSinceReset = 0;
    double error = 0.0;      // Mean |output - truth| over the non-sky pixels of the region.
    std::vector<std::vector<float>> outputs; // Per output type, RGBA.
};

class Rig
{
public:
    Rig(lab::VulkanContext& context, Method method) : m_Context(context), m_Method(method), m_Traits(TraitsOf(method))
    {
        DiscoverResources(method, m_Traits, m_Inputs, m_Outputs);
    }

    ~Rig()
    {
        m_Integration.Destroy();
        for (auto& texture : m_Textures)
            m_Context.DestroyTexture(texture.second);
    }

    const MethodTraits& Traits() const { return m_Traits; }
    bool Reads(ResourceType type) const { return std::find(m_Inputs.begin(), m_Inputs.end(), type) != m_Inputs.end(); }
    Integration& GetIntegration() { return m_Integration; }
    ResourceType Output(size_t i) const { return m_Outputs[i]; }

    // A fresh history at 'width' x 'height' with default settings and zeroed outputs.
    void Begin(uint16_t width, uint16_t height, rhi::Format outputFormat)
    {
        m_OutputFormat = outputFormat;
        if (!m_Created)
        {
            MethodDesc methodDesc = {kId, m_Method};
            DenoiserCreationDesc desc;
            desc.methods = &methodDesc;
            desc.methodsNum = 1;
            desc.renderWidth = width;
            desc.renderHeight = height;
            IntegrationCreationDesc integrationDesc = m_Context.GetIntegrationCreationDesc();
            integrationDesc.name = GetMethodString(m_Method);
            REQUIRE(m_Integration.Create(integrationDesc, desc) == VK_SUCCESS);
            m_Created = true;
        }
        if (m_Traits.applyDefaults)
            REQUIRE(m_Traits.applyDefaults.integration(m_Integration) == Result::SUCCESS);
        m_BadSettingsActive = false;
        m_PermanentPoolFilled = false;
        Resize(width, height);
    }

    void Resize(uint16_t width, uint16_t height)
    {
        REQUIRE(m_Integration.Resize(width, height) == VK_SUCCESS); // Pools re-created and cleared.
        m_Width = width;
        m_Height = height;
        for (auto& texture : m_Textures)
            m_Context.DestroyTexture(texture.second);
        m_Textures.clear();
        for (ResourceType type : m_Inputs)
        {
            bool bitmask = type == ResourceType::IN_SHADOW_BITMASK;
            rhi::Format format = bitmask ? rhi::Format::R32_UINT : rhi::Format::RGBA32_SFLOAT;
            uint32_t w = bitmask ? (width + 7u) / 8u : width, h = bitmask ? (height + 3u) / 4u : height;
            REQUIRE(m_Context.CreateTexture(format, w, h, GetResourceTypeString(type), m_Textures[type]) == VK_SUCCESS);
        }
        std::vector<float> zeros(size_t(width) * height * 4, 0.0f);
        for (ResourceType type : m_Outputs)
        {
            REQUIRE(m_Context.CreateTexture(m_OutputFormat, width, height, GetResourceTypeString(type), m_Textures[type]) ==
                    VK_SUCCESS);
            REQUIRE(m_Context.UploadTexture(m_Textures[type], zeros.data(), rhi::Layout::GENERAL) == VK_SUCCESS);
        }
    }

    // 'seed': the noise of the signal inputs (frames since the history started, so that a restart
    // replays the clean run's inputs).
    // 'variant': the second run of a case compared bit for bit (Case::skyInputsGarbage,
    // permanentPoolFill, worldOriginVariant).
    void RunFrame(const Case& c, const FramePlan& f, uint32_t seed, FrameRecord& record, bool variant = false)
    {
        if (f.width != m_Width || f.height != m_Height)
            Resize(f.width, f.height);
        uint32_t rw = f.resourceWidth ? f.resourceWidth : f.width, rh = f.resourceHeight ? f.resourceHeight : f.height;

        // Method settings: the case's on bad frames, the defaults otherwise.
        if (c.applyBad && f.bad != m_BadSettingsActive)
        {
            const SettingsCall& call = f.bad ? c.applyBad : m_Traits.applyDefaults;
            REQUIRE(call.integration(m_Integration) == Result::SUCCESS);
            m_BadSettingsActive = f.bad;
        }

        if (c.frameSettings)
            REQUIRE(c.frameSettings(seed).integration(m_Integration) == Result::SUCCESS);

        for (ResourceType type : m_Inputs)
            UploadInput(type, c, f, seed, rw, rh, variant && c.skyInputsGarbage, variant && c.permanentPoolFill);

        if (!f.skipCommonSettings)
        {
            CommonSettings settings = test::StillCameraSettings(f.frameIndex, f.resourceWidth, f.resourceHeight);
            settings.accumulationMode = f.mode;
            if (f.bad && c.editCommon)
                c.editCommon(settings);
            if (variant && c.worldOriginVariant != 0.0f)
                for (float* m : {settings.worldToViewMatrix, settings.worldToViewMatrixPrev})
                    for (int row = 0; row < 3; row++)
                        m[12 + row] -= c.worldOriginVariant; // Column-major, rotation identity.

            REQUIRE(m_Integration.SetCommonSettings(settings) == Result::SUCCESS);
        }

        test::Bindings bindings;
        for (auto& texture : m_Textures)
            bindings.push_back({texture.first, &texture.second});
        PoisonTransients();
        if (variant && c.permanentPoolFill)
            FillTransientsAndOutputs(c.permanentPoolFill);
        REQUIRE(test::DenoiseAndWait(m_Context, m_Integration, bindings) == VK_SUCCESS);

        record.width = f.width;
        record.height = f.height;
        record.regionWidth = uint16_t(rw);
        record.regionHeight = uint16_t(rh);
        record.outputs.resize(m_Outputs.size());
        double error = 0.0;
        for (size_t i = 0; i < m_Outputs.size(); i++)
        {
            REQUIRE(m_Context.ReadbackTexture(m_Textures[m_Outputs[i]], record.outputs[i]) == VK_SUCCESS);
            INFO(GetResourceTypeString(m_Outputs[i]) << " in " << rhi::GetFormatInfo(m_OutputFormat).name << ": "
                                                     << FirstNonFinite(record.outputs[i], f.width, 4));
            if (variant && c.permanentPoolFill) // The filled outputs keep NaN where nothing is written.
                CHECK(CountNonFiniteWritten(record.outputs[i], f.width, rw, rh) == 0);
            else
                CHECK(CountNonFinite(record.outputs[i]) == 0);
            error += OutputError(m_Outputs[i], record.outputs[i], f.width, rw, rh);
        }
        record.error = m_Outputs.empty() ? 0.0 : error / double(m_Outputs.size());
        CheckPools();
        m_TransientsFilled = false;
    }

private:
    // Mean |output - truth|: OUT_RADIANCE and OUT_*_RADIANCE_HITDIST all channels (.w: the hit
    // distance, truth the visibility), OUT_*_CONFIDENCE .x against 1 (the gradients say the
    // lighting never changes), any other output its .x (visibility, hit distance).
    static double OutputError(ResourceType type, const std::vector<float>& out, uint32_t width, uint32_t rw, uint32_t rh)
    {
        bool radiance = type == ResourceType::OUT_RADIANCE || type == ResourceType::OUT_DIFF_RADIANCE_HITDIST ||
                        type == ResourceType::OUT_SPEC_RADIANCE_HITDIST;
        double sum = 0.0;
        size_t num = 0;
        for (uint32_t y = 0; y < rh; y++)
            for (uint32_t x = 0; x < rw; x++)
            {
                if (IsSkyRow(y, rh))
                    continue;
                bool confidence = type == ResourceType::OUT_DIFF_CONFIDENCE || type == ResourceType::OUT_SPEC_CONFIDENCE;
                float p = confidence ? 1.0f : MeanVisibility(x, rw);
                const float* o = &out[(size_t(y) * width + x) * 4];
                for (uint32_t ch = 0; ch < (radiance ? 4u : 1u); ch++)
                {
                    sum += std::fabs(double(o[ch]) - double(p * (radiance ? kRadianceColor[ch] : 1.0f)));
                    num++;
                }
            }
        return num ? sum / double(num) : 0.0;
    }

    // 'outsideGarbage': the texels beyond a dynamic resolution's region hold NaN (bitmasks: a
    // pattern), what a larger render target holds there.
    void UploadInput(ResourceType type, const Case& c, const FramePlan& f, uint32_t seed, uint32_t rw, uint32_t rh,
                     bool skyGarbage, bool outsideGarbage)
    {
        lab::LabTexture& texture = m_Textures[type];
        if (type == ResourceType::IN_SHADOW_BITMASK)
        {
            // Texel (x / 8, y / 4), bit (x % 8) + 8 * (y % 4): lit; pixels outside the image are lit.
            std::vector<uint32_t> bits(size_t(texture.width) * texture.height, 0u);
            for (uint32_t y = 0; y < texture.height * 4; y++)
                for (uint32_t x = 0; x < texture.width * 8; x++)
                {
                    bool outside = x >= rw || y >= rh;
                    bool lit = outside ? !outsideGarbage || (x + 3 * y) % 5 < 2 : Visibility(seed, x, y, rw) > 0.5f;
                    if (lit)
                        bits[size_t(y / 4) * texture.width + x / 8] |= 1u << ((x % 8) + 8 * (y % 4));
                }
            UploadBytes(texture, bits.data());
            return;
        }

        std::vector<float> pixels(size_t(texture.width) * texture.height * 4, 0.0f);
        for (uint32_t y = 0; y < texture.height; y++)
            for (uint32_t x = 0; x < texture.width; x++)
            {
                float* p = &pixels[(size_t(y) * texture.width + x) * 4];
                float vis = Visibility(seed, x, y, rw);
                switch (type)
                {
                case ResourceType::IN_MV:
                    if (c.subPixelMotion != 0)
                    {
                        p[0] = -0.37f * float(c.subPixelMotion) / float(rw);
                        p[1] = -0.41f * float(c.subPixelMotion) / float(rh);
                    }
                    break;
                case ResourceType::IN_NORMAL_ROUGHNESS:
                    p[0] = 0.5f;
                    p[1] = 0.5f;
                    p[2] = 0.0f; // n = (0, 0, -1): towards the camera (view = world, looking along +z).
                    p[3] = 0.5f;
                    break;
                case ResourceType::IN_VIEWZ: p[0] = IsSkyRow(y, rh) ? kSkyViewZ : kPlaneViewZ; break;
                case ResourceType::IN_SHADOWDATA:
                    p[0] = vis;
                    p[1] = vis > 0.5f ? 65504.0f : kPenumbraOverViewZ;
                    break;
                case ResourceType::IN_SHADOW_TRANSLUCENCY:
                    p[0] = vis;
                    p[1] = p[2] = p[3] = vis > 0.5f ? 1.0f : 0.5f;
                    break;
                case ResourceType::IN_RADIANCE:
                    for (int ch = 0; ch < 4; ch++)
                        p[ch] = vis * kRadianceColor[ch];
                    break;
                case ResourceType::IN_SHADOW_VISIBILITY: p[0] = vis; break;
                case ResourceType::IN_DIFF_RADIANCE_HITDIST:
                case ResourceType::IN_SPEC_RADIANCE_HITDIST:
                    // Radiance as IN_RADIANCE; the normalized hit distance is the visibility (a miss
                    // where lit, an occluder at the surface where shadowed).
                    for (int ch = 0; ch < 4; ch++)
                        p[ch] = vis * kRadianceColor[ch];
                    break;
                case ResourceType::IN_DIFF_HITDIST:
                case ResourceType::IN_SPEC_HITDIST: p[0] = vis; break;
                case ResourceType::IN_DIFF_CONFIDENCE:
                case ResourceType::IN_SPEC_CONFIDENCE: p[0] = 1.0f; break;
                case ResourceType::IN_GRADIENTS:
                    // Unchanged lighting (difference 0) on a noisy luminance: confidence 1.
                    p[0] = p[2] = 0.0f;
                    p[1] = p[3] = vis + 0.05f;
                    break;
                default: break;
                }
                if (f.bad && c.edit && (TargetsOf(type) & c.targets) && x < rw && y < rh &&
                    InBadRegion(x, y, rw, rh, c.wholeImage))
                    c.edit(p);
                // The sky's inputs other than viewZ and motion (IN_GRADIENTS, at a third of the
                // resolution, has no sky rows of its own).
                uint32_t garbageTargets = SIGNAL | NORMAL | ROUGHNESS | CONFIDENCE;
                if (skyGarbage && IsSkyRow(y, rh) && x < rw && (TargetsOf(type) & garbageTargets) &&
                    type != ResourceType::IN_GRADIENTS)
                {
                    const float finite[4] = {type == ResourceType::IN_NORMAL_ROUGHNESS ? 0.9f : 37.5f,
                                             type == ResourceType::IN_NORMAL_ROUGHNESS ? 0.1f : 11.0f,
                                             type == ResourceType::IN_NORMAL_ROUGHNESS ? 0.3f : 2.25f,
                                             type == ResourceType::IN_NORMAL_ROUGHNESS ? 0.93f : 0.3f};
                    for (int ch = 0; ch < 4; ch++)
                        p[ch] = c.skyInputsNaN ? kNaN : finite[ch];
                }
                // IN_GRADIENTS: a texel per 3x3 stratum of the region.
                uint32_t regionW = type == ResourceType::IN_GRADIENTS ? (rw + 2) / 3 : rw;
                uint32_t regionH = type == ResourceType::IN_GRADIENTS ? (rh + 2) / 3 : rh;
                if (outsideGarbage && (x >= regionW || y >= regionH))
                    for (int ch = 0; ch < 4; ch++)
                        p[ch] = kNaN;
            }
        REQUIRE(m_Context.UploadTexture(texture, pixels.data()) == VK_SUCCESS);
    }

    // Raw texel upload (32-bit masks do not survive a trip through float).
    void UploadBytes(lab::LabTexture& texture, const void* bytes)
    {
        rhi::Device& device = m_Context.GetDevice();
        rhi::BufferDesc stagingDesc = {};
        stagingDesc.size = uint64_t(texture.width) * texture.height * rhi::GetFormatBytesPerPixel(texture.format);
        stagingDesc.usage = rhi::BUFFER_USAGE_COPY_SOURCE;
        stagingDesc.location = rhi::MemoryLocation::HOST_UPLOAD;
        rhi::Buffer* staging = nullptr;
        REQUIRE(device.CreateBuffer(stagingDesc, staging) == rhi::Result::SUCCESS);
        std::memcpy(device.MapBuffer(*staging), bytes, size_t(stagingDesc.size));
        VkCommandBuffer commandBuffer = VK_NULL_HANDLE;
        REQUIRE(m_Context.BeginCommands(commandBuffer) == VK_SUCCESS);
        rhi::CommandBuffer& cmd = rhi::GetCommandBuffer(commandBuffer);
        // WAR / WAW against the last Denoise, then RAW for the next one.
        rhi::TextureBarrier toCopy = {texture.texture, texture.state,
                                      {rhi::ACCESS_COPY_DESTINATION, rhi::Layout::COPY_DESTINATION}};
        device.CmdBarrier(cmd, {nullptr, 0, nullptr, 0, &toCopy, 1});
        device.CmdCopyBufferToTexture(cmd, *texture.texture, *staging, 0);
        rhi::TextureBarrier toRead = {texture.texture, toCopy.after, {rhi::ACCESS_SHADER_READ, rhi::Layout::SHADER_RESOURCE}};
        device.CmdBarrier(cmd, {nullptr, 0, nullptr, 0, &toRead, 1});
        REQUIRE(m_Context.SubmitAndWait(commandBuffer) == VK_SUCCESS);
        texture.state = toRead.after;
        device.DestroyBuffer(staging);
    }

    // Transient textures hold nothing between frames (an engine aliases them with its own data): fill
    // the float ones with a NaN of a recognizable payload before each frame. A method that reads a
    // transient pixel it did not write this frame then shows NaN in an output or the history.
    void PoisonTransients()
    {
        const DenoiserDesc& desc = m_Integration.GetDenoiserDesc();
        std::vector<Integration::PoolImage> images;
        uint64_t bytes = 0;
        for (uint32_t i = 0; i < desc.transientPoolSize; i++)
        {
            Integration::PoolImage image = m_Integration.GetPoolImage(ResourceType::TRANSIENT_POOL, i);
            rhi::Format format = rhi::FromVkFormat(image.format);
            if (image.layout == VK_IMAGE_LAYOUT_UNDEFINED || !IsFloatFormat(format) || format == rhi::Format::R11_G11_B10_UFLOAT)
                continue;
            images.push_back(image);
            bytes = std::max<uint64_t>(bytes, uint64_t(image.width) * image.height * rhi::GetFormatBytesPerPixel(format));
        }
        if (images.empty())
            return;
        bytes = (bytes + 15) / 16 * 16; // The fp16 half starts at a multiple of every texel size.

        // One staging area: fp32 poison words, then fp16 poison halves.
        std::vector<uint8_t> staging(size_t(bytes * 2));
        for (uint64_t i = 0; i < bytes; i += 4)
            std::memcpy(&staging[size_t(i)], &kPoison32, 4);
        for (uint64_t i = 0; i < bytes; i += 2)
            std::memcpy(&staging[size_t(bytes + i)], &kPoison16, 2);
        CopyToPoolImages(images, staging, [bytes](const Integration::PoolImage& image) {
            const rhi::FormatInfo& info = rhi::GetFormatInfo(rhi::FromVkFormat(image.format));
            return info.bytesPerPixel == 2 * info.channelNum ? bytes : 0;
        });
    }

public:
    // Every byte of every permanent pool texture set to 'pattern' (between two Denoise calls).
    void FillPermanentPool(uint8_t pattern)
    {
        FillPool(ResourceType::PERMANENT_POOL, pattern);
        m_PermanentPoolFilled = true; // Texels no pass writes keep the pattern (NaN or not).
    }

    // Before a frame: every byte of every transient pool texture, and every value of the outputs, set
    // to 'pattern' (what another user of the memory left; outputs hold NaN for all ones, else 0.75).
    void FillTransientsAndOutputs(uint8_t pattern)
    {
        FillPool(ResourceType::TRANSIENT_POOL, pattern);
        m_TransientsFilled = true; // For this frame: texels no pass writes keep the pattern.
        float value = pattern == 0xff ? kNaN : 0.75f;
        for (ResourceType type : m_Outputs)
        {
            lab::LabTexture& texture = m_Textures[type];
            std::vector<float> values(size_t(texture.width) * texture.height * 4, value);
            REQUIRE(m_Context.UploadTexture(texture, values.data(), rhi::Layout::GENERAL) == VK_SUCCESS);
        }
    }

private:
    void FillPool(ResourceType pool, uint8_t pattern)
    {
        const DenoiserDesc& desc = m_Integration.GetDenoiserDesc();
        uint32_t num = pool == ResourceType::PERMANENT_POOL ? desc.permanentPoolSize : desc.transientPoolSize;
        std::vector<Integration::PoolImage> images;
        uint64_t bytes = 0;
        for (uint32_t i = 0; i < num; i++)
        {
            Integration::PoolImage image = m_Integration.GetPoolImage(pool, i);
            if (image.layout == VK_IMAGE_LAYOUT_UNDEFINED) // Cleared by the first Denoise that uses it.
                continue;
            images.push_back(image);
            bytes = std::max<uint64_t>(bytes, uint64_t(image.width) * image.height *
                                                  rhi::GetFormatBytesPerPixel(rhi::FromVkFormat(image.format)));
        }
        if (!images.empty())
            CopyToPoolImages(images, std::vector<uint8_t>(size_t(bytes), pattern),
                             [](const Integration::PoolImage&) { return uint64_t(0); });
    }

    // Copies 'bytes' from offset 'offsetOf(image)' into each of 'images' (tightly packed texels),
    // leaving each in the state the Integration tracks.
    void CopyToPoolImages(const std::vector<Integration::PoolImage>& images, const std::vector<uint8_t>& bytes,
                          const std::function<uint64_t(const Integration::PoolImage&)>& offsetOf)
    {
        rhi::Device& device = m_Device();
        rhi::BufferDesc stagingDesc = {};
        stagingDesc.size = bytes.size();
        stagingDesc.usage = rhi::BUFFER_USAGE_COPY_SOURCE;
        stagingDesc.location = rhi::MemoryLocation::HOST_UPLOAD;
        rhi::Buffer* staging = nullptr;
        REQUIRE(device.CreateBuffer(stagingDesc, staging) == rhi::Result::SUCCESS);
        std::memcpy(device.MapBuffer(*staging), bytes.data(), bytes.size());

        VkCommandBuffer commandBuffer = VK_NULL_HANDLE;
        REQUIRE(m_Context.BeginCommands(commandBuffer) == VK_SUCCESS);
        rhi::CommandBuffer& cmd = rhi::GetCommandBuffer(commandBuffer);
        rhi::TextureState copyState = {rhi::ACCESS_COPY_DESTINATION, rhi::Layout::COPY_DESTINATION};
        for (const Integration::PoolImage& image : images)
        {
            // WAR / WAW against the last Denoise; afterwards back to the state the Integration tracks
            // (RAW for the next Denoise).
            rhi::TextureBarrier toCopy = {image.texture, image.state, copyState};
            device.CmdBarrier(cmd, {nullptr, 0, nullptr, 0, &toCopy, 1});
            device.CmdCopyBufferToTexture(cmd, *image.texture, *staging, offsetOf(image));
            rhi::TextureBarrier back = {image.texture, copyState, image.state};
            device.CmdBarrier(cmd, {nullptr, 0, nullptr, 0, &back, 1});
        }
        REQUIRE(m_Context.SubmitAndWait(commandBuffer) == VK_SUCCESS);
        device.DestroyBuffer(staging);
    }

    static bool IsPoison(float value)
    {
        uint32_t bits;
        std::memcpy(&bits, &value, 4);
        return bits == kPoison32 || bits == kPoison16AsFloat;
    }

    rhi::Device& m_Device() { return m_Context.GetDevice(); }

    // Every float pool texture: no NaN / Inf (transient ones: but the poison of pixels no pass
    // wrote this frame). Read back, then returned to the state the Integration tracks (its next
    // barriers start from there).
    void CheckPools()
    {
        const DenoiserDesc& desc = m_Integration.GetDenoiserDesc();
        std::vector<rhi::TextureBarrier> restore;
        for (ResourceType pool : {ResourceType::PERMANENT_POOL, ResourceType::TRANSIENT_POOL})
        {
            if ((pool == ResourceType::PERMANENT_POOL && m_PermanentPoolFilled) || (pool == ResourceType::TRANSIENT_POOL && m_TransientsFilled))
                continue;
            uint32_t num = pool == ResourceType::PERMANENT_POOL ? desc.permanentPoolSize : desc.transientPoolSize;
            for (uint32_t i = 0; i < num; i++)
            {
                Integration::PoolImage image = m_Integration.GetPoolImage(pool, i);
                REQUIRE(image.texture != nullptr);
                rhi::Format format = rhi::FromVkFormat(image.format);
                if (image.layout == VK_IMAGE_LAYOUT_UNDEFINED || !IsFloatFormat(format))
                    continue;
                if (format == rhi::Format::R11_G11_B10_UFLOAT)
                {
                    WARN("a pool texture in R11_G11_B10_UFLOAT is not read back (no converter)");
                    continue;
                }
                lab::LabTexture view = test::PoolTextureView(image);
                std::vector<float> pixels;
                REQUIRE(m_Context.ReadbackTexture(view, pixels) == VK_SUCCESS);
                if (pool == ResourceType::TRANSIENT_POOL)
                    for (float& value : pixels)
                        value = IsPoison(value) ? 0.0f : value;
                INFO(GetResourceTypeString(pool) << " " << i << " (" << rhi::GetFormatInfo(format).name << ", "
                                                  << image.width << "x" << image.height << "): "
                                                  << FirstNonFinite(pixels, image.width, rhi::GetFormatInfo(format).channelNum));
                CHECK(CountNonFinite(pixels) == 0);
                restore.push_back({image.texture, view.state, image.state});
            }
        }
        if (restore.empty())
            return;
        VkCommandBuffer commandBuffer = VK_NULL_HANDLE;
        REQUIRE(m_Context.BeginCommands(commandBuffer) == VK_SUCCESS);
        // WAR: the next Denoise's accesses wait for the readback copies; layouts as tracked.
        m_Context.GetDevice().CmdBarrier(rhi::GetCommandBuffer(commandBuffer),
                                         {nullptr, 0, nullptr, 0, restore.data(), uint32_t(restore.size())});
        REQUIRE(m_Context.SubmitAndWait(commandBuffer) == VK_SUCCESS);
    }

    lab::VulkanContext& m_Context;
    Method m_Method;
    MethodTraits m_Traits;
    std::vector<ResourceType> m_Inputs;
    std::vector<ResourceType> m_Outputs;
    Integration m_Integration;
    bool m_Created = false;
    bool m_BadSettingsActive = false;
    bool m_PermanentPoolFilled = false;
    bool m_TransientsFilled = false;
    uint16_t m_Width = 0, m_Height = 0;
    rhi::Format m_OutputFormat = rhi::Format::RGBA32_SFLOAT;
    std::map<ResourceType, lab::LabTexture> m_Textures;
};

// The context and the rigs live for the whole run (pipelines on lavapipe are not free).
struct World
{
    std::unique_ptr<lab::VulkanContext> context;
    std::map<Method, std::unique_ptr<Rig>> rigs;
    std::map<Method, uint32_t> rigUses;
    std::map<std::string, std::vector<double>> baselines;

    static World& Get()
    {
        static World world;
        return world;
    }

    lab::VulkanContext& Context()
    {
        if (!context)
            context = test::CreateValidatedContext();
        REQUIRE(context != nullptr);
        return *context;
    }

    // A method's rig serves kRigCases cases, then is created again: lavapipe keeps compiling shader
    // variants for the lifetime of a pipeline, and RELAX's grew the process by about 200 MB a case
    // (20 GB over one ctest slice of 80 cases, on a 24 GB machine).
    static constexpr uint32_t kRigCases = 6;
    Rig& GetRig(Method method)
    {
        std::unique_ptr<Rig>& rig = rigs[method];
        uint32_t& uses = rigUses[method];
        if (rig && uses >= kRigCases)
            rig.reset();
        if (!rig)
        {
            rig.reset(new Rig(Context(), method));
            uses = 0;
        }
        uses++;
        return *rig;
    }

    void Destroy()
    {
        rigs.clear();
        context.reset();
    }
};

struct WorldCleanup : Catch::TestEventListenerBase
{
    using TestEventListenerBase::TestEventListenerBase;
    void testRunEnded(Catch::TestRunStats const& stats) override
    {
        World::Get().Destroy();
        TestEventListenerBase::testRunEnded(stats);
    }
};

//==================================================================================================
// Running a case.
//==================================================================================================

// 'variant': the second run of a case compared bit for bit: the permanent pool filled before the
// second frame (Case::permanentPoolFill), the sky's inputs garbage (Case::skyInputsGarbage), the
// world's origin moved (Case::worldOriginVariant).
void RunPlan(Rig& rig, const Case& c, const std::vector<FramePlan>& plan, std::vector<FrameRecord>& records,
             bool variant = false)
{
    records.assign(plan.size(), FrameRecord());
    rig.Begin(plan.front().width, plan.front().height, c.outputFormat);
    uint32_t seed = 0;
    for (size_t t = 0; t < plan.size(); t++)
    {
        const FramePlan& f = plan[t];
        INFO("frame " << t << " (frameIndex " << f.frameIndex << (f.bad ? ", bad" : "") << ")");
        // History restarts (CommonSettings docs): frameIndex 0, RESTART, a new size.
        bool reset = t == 0 || (!f.skipCommonSettings && (f.frameIndex == 0 || f.mode == AccumulationMode::RESTART)) ||
                     f.width != plan[t - 1].width || f.height != plan[t - 1].height ||
                     f.resourceWidth != plan[t - 1].resourceWidth || f.resourceHeight != plan[t - 1].resourceHeight;
        records[t].framesSinceReset = reset ? 0 : records[t - 1].framesSinceReset + 1;
        if (!f.sameInputs)
            seed = records[t].framesSinceReset;
        if (variant && c.permanentPoolFill && t == 1)
            rig.FillPermanentPool(c.permanentPoolFill);
        rig.RunFrame(c, f, seed, records[t], variant);
    }
}

// Errors of a clean run per frames since the start of history, at one size; at least 'length' frames.
const std::vector<double>& Baseline(Rig& rig, Method method, const FrameRecord& config, rhi::Format outputFormat,
                                    uint32_t length)
{
    char key[128];
    std::snprintf(key, sizeof(key), "%s %ux%u region %ux%u format %u", GetMethodString(method), config.width,
                  config.height, config.regionWidth, config.regionHeight, uint32_t(outputFormat));
    std::vector<double>& errors = World::Get().baselines[key];
    if (errors.size() < length)
    {
        errors.clear();
        INFO("clean run " << key);
        Case clean;
        clean.outputFormat = outputFormat;
        std::vector<FramePlan> plan = CleanFrames(std::max(length, kBaselineFrames));
        bool dynamic = config.regionWidth != config.width || config.regionHeight != config.height;
        for (FramePlan& f : plan)
        {
            f.width = config.width;
            f.height = config.height;
            f.resourceWidth = dynamic ? config.regionWidth : 0;
            f.resourceHeight = dynamic ? config.regionHeight : 0;
        }
        std::vector<FrameRecord> records;
        RunPlan(rig, clean, plan, records);
        for (const FrameRecord& r : records)
            errors.push_back(r.error);
    }
    return errors;
}

uint32_t RecoveryFrames(const MethodTraits& traits, const Case& c)
{
    bool small = c.width < 8 || c.height < 8;
    return small && traits.smallImageRecoveryFrames ? traits.smallImageRecoveryFrames : traits.recoveryFrames;
}

std::vector<FramePlan> DefaultPlan(const Case& c, const MethodTraits& traits)
{
    std::vector<FramePlan> plan = CleanFrames(kWarmFrames);
    FramePlan bad;
    bad.bad = true;
    Append(plan, c.applyBad || c.editCommon ? kSettingsFrames : kBadFrames, bad);
    Append(plan, RecoveryFrames(traits, c) + 2, FramePlan());
    for (FramePlan& f : plan)
    {
        f.width = c.width;
        f.height = c.height;
    }
    return plan;
}

void RunCase(Method method, const Case& c)
{
    World& world = World::Get();
    lab::VulkanContext& context = world.Context();
    Rig& rig = world.GetRig(method);
    const MethodTraits& traits = rig.Traits();
    uint32_t messagesBefore = context.ValidationMessageCount();

    std::vector<FramePlan> plan = c.plan ? c.plan(traits.recoveryFrames) : DefaultPlan(c, traits);
    // Methods that keep every frame (REFERENCE) are restarted by the application after a disturbance.
    if (traits.recoversByRestart)
        for (size_t t = 1; t < plan.size(); t++)
            if ((plan[t - 1].bad || plan[t - 1].disturbance) && !plan[t].bad && !plan[t].disturbance)
                plan[t].mode = AccumulationMode::RESTART;

    // Out-of-range settings are rejected (and change nothing: the warm frames match the clean run).
    rig.Begin(plan.front().width, plan.front().height, c.outputFormat);
    for (const SettingsCall& call : c.rejected)
        CHECK(call.integration(rig.GetIntegration()) == Result::INVALID_ARGUMENT);
    for (const auto& edit : c.rejectedCommon)
    {
        CommonSettings settings = test::StillCameraSettings(0);
        edit(settings);
        CHECK(rig.GetIntegration().SetCommonSettings(settings) == Result::INVALID_ARGUMENT);
    }

    std::vector<FrameRecord> records;
    RunPlan(rig, c, plan, records);

    if (c.permanentPoolFill || c.skyInputsGarbage || c.worldOriginVariant != 0.0f)
    {
        // The same frames over a permanent pool of garbage, with garbage in the sky's inputs, or in a
        // world far from the origin: the same outputs, bit for bit.
        std::vector<FrameRecord> filled;
        RunPlan(rig, c, plan, filled, true);
        for (size_t t = 0; t < plan.size(); t++)
            for (size_t o = 0; o < records[t].outputs.size(); o++)
            {
                const std::vector<float>& a = records[t].outputs[o];
                const std::vector<float>& b = filled[t].outputs[o];
                REQUIRE(a.size() == b.size());
                size_t differ = 0, first = a.size(), writtenBeyond = 0;
                for (size_t i = 0; i < a.size(); i++)
                {
                    // Within the region; beyond it the filled run's outputs keep the fill (not written).
                    uint32_t x = uint32_t(i / 4 % records[t].width), y = uint32_t(i / 4 / records[t].width);
                    if (x >= records[t].regionWidth || y >= records[t].regionHeight)
                    {
                        if (c.permanentPoolFill)
                            writtenBeyond += c.permanentPoolFill == 0xff ? !std::isnan(b[i]) : b[i] != 0.75f;
                        continue;
                    }
                    // Sky pixels' outputs are not written (and the filled run's outputs were filled).
                    if (std::memcmp(&a[i], &b[i], sizeof(float)) != 0 && !IsSkyRow(y, records[t].regionHeight))
                    {
                        differ++;
                        first = std::min(first, i);
                    }
                }
                if (std::getenv("NRD_ROBUSTNESS_VERBOSE") && differ)
                {
                    std::printf("frame %zu output %zu:\n", t, o);
                    for (uint32_t y = 0; y < records[t].height; y++)
                    {
                        for (uint32_t x = 0; x < records[t].width; x++)
                            std::printf("%c", std::memcmp(&a[(size_t(y) * records[t].width + x) * 4], &b[(size_t(y) * records[t].width + x) * 4], 16) ? 'X' : '.');
                        std::printf("\n");
                    }
                }
                INFO("frame " << t << ", " << GetResourceTypeString(rig.Output(o)) << ": " << differ
                              << " values differ from the first run's; first at ("
                              << (first / 4) % records[t].width << ", " << (first / 4) / records[t].width << ")."
                              << first % 4 << ": " << (first < a.size() ? a[first] : 0.0f) << " against "
                              << (first < b.size() ? b[first] : 0.0f));
                CHECK(differ == 0);
                INFO("output values written beyond the region: " << writtenBeyond);
                CHECK(writtenBeyond == 0);
            }
        CHECK(context.ValidationMessageCount() == messagesBefore);
        return;
    }

    // Error against the clean run once recovered; documented behaviour during the bad frames.
    // NRD_ROBUSTNESS_VERBOSE=1 prints every frame (to measure recovery).
    const char* verboseEnv = std::getenv("NRD_ROBUSTNESS_VERBOSE");
    bool verbose = verboseEnv && verboseEnv[0] == '1';
    if (verbose)
        std::printf("%s / %s\n", GetMethodString(method), c.name.c_str());
    int lastDisturbance = -1;
    for (size_t t = 0; t < plan.size(); t++)
    {
        const FrameRecord& r = records[t];
        INFO("frame " << t << " (frameIndex " << plan[t].frameIndex << (plan[t].bad ? ", bad" : "") << ", " << r.width
                      << "x" << r.height << ", region " << r.regionWidth << "x" << r.regionHeight << ")");
        bool duringBad = plan[t].bad || plan[t].disturbance;
        if (duringBad)
            lastDisturbance = int(t);

        if (plan[t].bad && c.badIsSky && rig.Reads(ResourceType::IN_VIEWZ) && t > 0)
        {
            // Sky is neither denoised nor written: the bad pixels keep the previous frame's output.
            size_t written = 0;
            for (size_t o = 0; o < r.outputs.size(); o++)
                for (uint32_t y = 0; y < r.regionHeight; y++)
                    for (uint32_t x = 0; x < r.regionWidth; x++)
                    {
                        if (!InBadRegion(x, y, r.regionWidth, r.regionHeight, c.wholeImage))
                            continue;
                        size_t i = (size_t(y) * r.width + x) * 4;
                        written += std::memcmp(&r.outputs[o][i], &records[t - 1].outputs[o][i], 4 * sizeof(float)) != 0;
                    }
            INFO("sky pixels written: " << written);
            CHECK(written == 0);
        }

        bool recovered = lastDisturbance < 0 || int(t) - lastDisturbance >= int(RecoveryFrames(traits, c));
        if ((duringBad ? !c.badIsIgnored : !recovered) && !verbose)
            continue;
        const std::vector<double>& baseline = Baseline(rig, method, r, c.outputFormat, r.framesSinceReset + 1);
        double clean = baseline[r.framesSinceReset];
        if (verbose)
            std::printf("  frame %2zu%s: error %.5f, clean %.5f (x%.2f)\n", t, duringBad ? " bad" : "    ", r.error, clean,
                        clean > 0.0 ? r.error / clean : 0.0);
        INFO("error " << r.error << ", clean run " << clean << " at " << r.framesSinceReset << " frames of history");
        if (duringBad ? c.badIsIgnored : recovered)
            CHECK(r.error <= kRecoveryFactor * clean + kRecoveryTolerance);
    }

    CHECK(context.ValidationMessageCount() == messagesBefore);
}

//==================================================================================================
// Registration: one Catch test per method and applicable case, named "<METHOD> / <case>".
//==================================================================================================

std::map<Method, std::vector<Case>>& Registered()
{
    static std::map<Method, std::vector<Case>> cases;
    return cases;
}

struct CaseInvoker : Catch::ITestInvoker
{
    Method method;
    size_t index;
    CaseInvoker(Method m, size_t i) : method(m), index(i) {}
    void invoke() const override { RunCase(method, Registered()[method][index]); }
};

bool RegisterCases()
{
    const LibraryDesc& library = GetLibraryDesc();
    std::vector<Case> generic = GenericCases();
    for (uint32_t m = 0; m < library.supportedMethodsNum; m++)
    {
        Method method = library.supportedMethods[m];
        MethodTraits traits = TraitsOf(method);
        if (traits.coveredBy != Method::MAX_NUM)
            continue;
        std::vector<ResourceType> inputs, outputs;
        DiscoverResources(method, traits, inputs, outputs);
        uint32_t reads = 0;
        for (ResourceType type : inputs)
            reads |= TargetsOf(type);
        bool boundedOutputs = std::find(outputs.begin(), outputs.end(), ResourceType::OUT_RADIANCE) == outputs.end();

        std::vector<Case>& cases = Registered()[method];
        for (const Case& c : generic)
            if ((c.targets == 0 || (c.targets & reads) != 0) && (boundedOutputs || !c.needsBoundedOutputs))
                cases.push_back(c);
        for (const Case& c : traits.settingsCases)
            cases.push_back(c);
        for (const auto& variant : traits.poolVariants)
            for (const Case& c : generic)
                if (c.tag == "pools" && c.worldOriginVariant == 0.0f)
                {
                    Case v = c;
                    v.name += ", " + variant.first;
                    v.frameSettings = variant.second;
                    cases.push_back(v);
                }
        for (size_t i = 0; i < cases.size(); i++)
        {
            std::string name = std::string(GetMethodString(method)) + " / " + cases[i].name;
            std::string tags = std::string("[robustness][") + GetMethodString(method) + "][" + cases[i].tag + "]";
            Catch::AutoReg(new CaseInvoker(method, i), Catch::SourceLineInfo(__FILE__, __LINE__), Catch::StringRef(),
                           Catch::NameAndTags(name, tags));
        }
    }
    return true;
}

const bool g_Registered = RegisterCases();

} // namespace

CATCH_REGISTER_LISTENER(WorldCleanup)
