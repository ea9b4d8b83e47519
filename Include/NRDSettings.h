// Per-frame settings. Defaults are the recommended values.
#pragma once

#include <cstdint>

#ifndef NRD_VERSION_MAJOR
#  error "Include NRD.h instead of NRDSettings.h"
#endif

namespace nrd
{

static_assert(NRD_VERSION_MAJOR == 0 && NRD_VERSION_MINOR == 1, "NRDSettings.h does not match NRD.h");

enum class AccumulationMode : uint8_t
{
    CONTINUE, // Use history.
    RESTART,  // Discard history this frame (same as frameIndex == 0).
};

// Matrices are column-major (m[column * 4 + row]) and non-jittered. viewToClip is a perspective
// projection whose clip w equals the positive view depth (IN_VIEWZ): w = +z or w = -z, so both
// right- and left-handed view spaces work. Clip space is Vulkan's: x, y in [-1, 1], y down, so
// uv = (ndc.xy * 0.5 + 0.5) addresses the texture with v growing downwards. The world may lie far
// from its origin: the denoisers work relative to the camera (products formed in double), so only
// the precision of the float matrices themselves limits them.
struct CommonSettings
{
    float viewToClipMatrix[16] = {};
    float viewToClipMatrixPrev[16] = {};
    float worldToViewMatrix[16] = {};
    float worldToViewMatrixPrev[16] = {};

    // Multiplies IN_MV: 2D uvPrev = uv + mv.xy * scale.xy; 3D posPrev = pos + mv.xyz * scale.
    // Must be finite. {0, 0, 0} ignores IN_MV (camera motion is still tracked via the matrices).
    float motionVectorScale[3] = {1.0f, 1.0f, 0.0f};

    // Sub-pixel jitter of this and the previous frame, in pixels, each in [-0.5, 0.5].
    float cameraJitter[2] = {};
    float cameraJitterPrev[2] = {};

    // Size of the inputs this frame, in pixels, 1..creation size. 0 means the creation size.
    uint16_t resourceSize[2] = {};

    // Pixels with |viewZ| beyond this (or non-finite viewZ) are sky: not denoised, not written.
    float denoisingRange = 500000.0f;

    // Relative depth difference above which history is considered disoccluded.
    float disocclusionThreshold = 0.01f;

    // Frame counter. 0 (or accumulationMode RESTART) restarts history this frame.
    uint32_t frameIndex = 0;
    AccumulationMode accumulationMode = AccumulationMode::CONTINUE;

    // IN_MV holds world-space 3D motion (true) or screen-space 2D uv motion (false).
    bool isMotionVectorInWorldSpace = false;
};

// Hit distance normalization of the radiance + hit distance methods (REBLUR, RELAX): a hit distance
// is stored as hitDist / f, saturated to [0, 1], with
//     f = (A + |viewZ| * B) * lerp(1, C, saturate(exp2(D * roughness^2)))
// (REBLUR_FrontEnd_GetNormHitDist in Shaders/Include/NRD.glsl; roughness is linear, 1 for diffuse).
// A and B are in world units (scale them with the scene's units); C widens the range of near-mirror
// surfaces, whose reflections stay sharp farther away; D sets how fast that widening fades with
// roughness. The application must normalize with the same values it gives the method settings.
// Valid: all finite, A > 0, B >= 0, C >= 1, D <= 0 (ValidateHitDistanceParameters in NRD.h).
struct HitDistanceParameters
{
    float A = 3.0f;   // Constant part of the range, world units, > 0.
    float B = 0.1f;   // Part proportional to |viewZ|, >= 0.
    float C = 20.0f;  // Range multiplier at roughness 0, >= 1.
    float D = -25.0f; // Exponent of the roughness falloff of C (per roughness^2, base 2), <= 0.
};

// SIGMA_SHADOW and SIGMA_SHADOW_TRANSLUCENCY.
struct SigmaSettings
{
    // Direction towards an infinite light (world space, need not be normalized). Used to orient
    // the anisotropic penumbra blur; {0, 0, 0} means "unknown" (isotropic blur).
    float lightDirection[3] = {0.0f, 0.0f, 0.0f};

    // Moving lights. Shadows that a moving light carries across still surfaces have no motion
    // vectors; told where the light is every frame, SIGMA keeps a hard shadow's history only while
    // it holds less than 1/20 pixel of that motion (the history of a shadow that moved is the
    // shadow where it was). Either of:
    // - an infinite light: lightDirection and tan of its angular radius (the value given to
    //   SIGMA_FrontEnd_PackShadow), [0, 1]; a turn moves each shadow by tan(turn) / this many
    //   penumbra radii (a time-of-day sun);
    // - a sphere light: its world-space position and radius, (0, 1e6]; a move moves each shadow by the
    //   light's displacement across the direction to it, over the radius, penumbra radii.
    // 0 (the defaults) means unknown: the history is left to the neighbourhood rules alone. The
    // sphere light wins where both are set. One light: where IN_SHADOWDATA packs several
    // (SIGMA_FrontEnd_MultiLight*), the shadows of the others would be taken for moving ones; leave
    // these at 0 unless they all move together.
    // The same light also places each shadow's occluder (toward the light, at the distance its
    // penumbra gives): where the occluder is in view and its motion vector says it moved, a hard
    // shadow keeps as little history as a moving light's (an animated object's shadow on a still
    // floor), where the penumbrae around are under a pixel and those next to it under half a pixel.
    // And it marks the light's terminator (less than half of the light's disk above the surface's
    // tangent plane, by IN_NORMAL_ROUGHNESS): there a lit hard-shadow sample under camera motion takes
    // the running mean of its samples (a sphere's self-shadow edge, whose penumbra estimate is 0).
    float tanOfLightAngularRadius = 0.0f;
    float lightPosition[3] = {0.0f, 0.0f, 0.0f};
    float lightRadius = 0.0f;

    // Geometry edge stopping: relative plane distance tolerance, (0, 1].
    float planeDistanceSensitivity = 0.02f;

    // Scales the penumbra-derived blur radius, [0, 8]. 2-4 helps against shimmering.
    float blurRadiusScale = 1.0f;

    // Temporal stabilization length in frames, [0, SIGMA_MAX_HISTORY_FRAME_NUM]. 0 disables it.
    uint32_t maxStabilizedFrameNum = 5;
};

constexpr uint32_t SIGMA_MAX_HISTORY_FRAME_NUM = 31;
constexpr float SIGMA_MAX_BLUR_RADIUS_SCALE = 8.0f;

// REFERENCE.
struct ReferenceSettings
{
    // Running mean over at most this many frames, [1, REFERENCE_MAX_HISTORY_FRAME_NUM]; beyond it
    // the mean becomes an exponential moving average with alpha 1 / maxAccumulatedFrameNum.
    uint32_t maxAccumulatedFrameNum = 1023;
};

constexpr uint32_t REFERENCE_MAX_HISTORY_FRAME_NUM = 65535;

// What TILED_SHADOW writes to OUT_SHADOW_TRANSLUCENCY (all channels). Anything but NONE is a
// debugging view: every pixel is written, sky included; of the a-trous passes only the first runs
// (it stores the history), without writing OUT_SHADOW_TRANSLUCENCY.
enum class TiledShadowDebug : uint8_t
{
    NONE,              // The denoised visibility.
    LOCAL_MEAN,        // Gaussian-weighted mean of the bitmask over the (2 * neighborhoodRadius + 1)^2
                       // neighbourhood, pixels outside the image excluded (document 000, "local
                       // neighborhood encoding"). Its variance is LOCAL_MEAN * (1 - LOCAL_MEAN).
    TEMPORAL_VARIANCE, // Variance handed to the first filter pass (temporal, boosted on short history).
    HISTORY_LENGTH,    // Accumulated samples / TILED_SHADOW_MAX_HISTORY_FRAME_NUM, in [0, 1].
    TILE_CLASS,        // Class of the pixel's 8x4 tile: 0 filtered, 0.25 skipped (lit neighbourhood),
                       // 0.5 skipped (shadowed neighbourhood), 0.75 skipped (sky only).
    MAX_NUM
};

// TILED_SHADOW.
//
// Tile classification: a tile is skipped (written as fully lit or fully shadowed, never filtered)
// when every in-image bit of the 3x5 tiles around it (the tile, one tile left and right, two tiles
// up and down: everything its pixels' neighbourhoods and the a-trous passes reach) is equal. A tile
// whose pixels are all sky is skipped too. Per frame counts are kept in the method's buffer (see
// TILED_SHADOW_COUNTERS_* below) and shown by TiledShadowDebug::TILE_CLASS.
struct TiledShadowSettings
{
    // The application writes IN_SHADOW_BITMASK itself (the prepare pass is skipped) instead of
    // IN_SHADOW_VISIBILITY.
    bool isBitmaskInput = false;

    // Skip tiles without spatial variance. Off: every tile is filtered (for comparisons).
    bool enableTileSkipping = true;

    // Radius of the local neighbourhood (mean and variance for the history clamp), [1, 8]; 8 is the
    // 17x17 kernel of the document. Weights exp(-3 i^2 / (radius + 1)^2) along each axis.
    uint32_t neighborhoodRadius = 8;

    // History clamp: where the local neighbourhood changed (its mean moved beyond 2 standard errors
    // from its running mean at the same surface point: a moving shadow), the reprojected history is
    // clamped to mean +- historyClampSigma * sigma of the neighbourhood, (0, 8]. A still
    // neighbourhood keeps its history unclamped (next to a sharp shadow edge the box would exclude
    // the pixel's own value).
    float historyClampSigma = 0.5f;

    // Disocclusion: largest relative depth tolerance, reached at grazing angles, (0, 1]. The
    // tolerance is CommonSettings::disocclusionThreshold plus the relative depth change of the
    // surface's tangent plane over 1.5 pixels, at most this.
    float disocclusionThresholdGrazing = 0.1f;

    // A-trous edge stopping: distance of a sample to the centre's tangent plane, relative to viewZ,
    // that drops its weight by 1/e, (0, 1].
    float planeDistanceSensitivity = 0.02f;

    // A-trous edge stopping: exponent of max(0, N.N'), [0, 128].
    float normalPower = 32.0f;

    // Edge-avoiding a-trous passes (steps 1, 2, 4), [1, 3]. Document 000 runs 3; the third (step 4)
    // blurs more than it denoises on the scene lab at 64x64 to 256x256 (Shaders/TiledShadow/README.md).
    uint32_t atrousPassNum = 2;

    // Longest history in frames, [1, TILED_SHADOW_MAX_HISTORY_FRAME_NUM]. The blend toward the
    // current frame is lerp(0.05, 1, sqrt(max(8 - n, 0) / 8)) for n accumulated frames (more under
    // sub-pixel camera motion, which resamples the history), and the variance is boosted while
    // n < 16, so values below 16 keep the spatial filter stronger.
    uint32_t maxHistoryFrameNum = 32;

    // Moving lights, as SigmaSettings' (a departure from document 000): with isShadowDataInput the
    // application also provides IN_SHADOWDATA (SIGMA_FrontEnd_PackShadow: the penumbra of each
    // shadowed sample) and, every frame, the light: an infinite light's direction and tan of its
    // angular radius ([0, 1]) or a sphere light's world-space position and radius ([0, 1e6]; wins
    // where both are set). A hard shadow (penumbra radius under a pixel) that the light's move since
    // the previous frame carried keeps at most 1/20 pixel of that motion in its history, and outputs
    // its sample where not a whole frame fits; so does one whose occluder (placed by the light and
    // the penumbra) is in view and moved, where the penumbrae around are under half a pixel, or under
    // a pixel with those next to it under half a pixel. A softer shadow whose occluder moved takes its
    // history where the shadow lay in the previous frame (the occluder's move projected along the
    // light onto the surface), as long as that estimate holds to a penumbra radius. A soft shadow
    // (penumbrae around under a pixel) that the light's move leaves under a frame of history outputs
    // the plus-shaped mean of its samples instead of the a-trous passes' wider blur. Zeros: unknown
    // (nothing changes).
    bool isShadowDataInput = false;
    float lightDirection[3] = {0.0f, 0.0f, 0.0f};
    float tanOfLightAngularRadius = 0.0f;
    float lightPosition[3] = {0.0f, 0.0f, 0.0f};
    float lightRadius = 0.0f;

    TiledShadowDebug debugView = TiledShadowDebug::NONE;
};

constexpr uint32_t TILED_SHADOW_MAX_HISTORY_FRAME_NUM = 63;
constexpr uint32_t TILED_SHADOW_MAX_NEIGHBORHOOD_RADIUS = 8;

// TILED_SHADOW counters: a permanent pool buffer (the last resource of the dispatch named
// "TILED_SHADOW - Classify"; zero-initialized by the application) of 2 x 4 uint32 slots. Frame n
// (counted from the denoiser's creation, from 1) accumulates into slot n % 2 and clears slot
// (n + 1) % 2; once its dispatches completed, the slot with the larger FRAME entry holds it.
constexpr uint32_t TILED_SHADOW_COUNTERS_SLOT_SIZE = 4;      // uint32 per slot.
constexpr uint32_t TILED_SHADOW_COUNTERS_UNIFORM_TILES = 0;  // Tiles skipped for a uniform neighbourhood.
constexpr uint32_t TILED_SHADOW_COUNTERS_SKY_TILES = 1;      // Other tiles skipped because all pixels are sky.
constexpr uint32_t TILED_SHADOW_COUNTERS_TOTAL_TILES = 2;    // DivideUp(width, 8) * DivideUp(height, 4).
constexpr uint32_t TILED_SHADOW_COUNTERS_FRAME = 3;          // Frame number n.

// REBLUR / RELAX checkerboard input: which pixels carry a traced sample this frame (the others
// are ignored and reconstructed from their traced neighbours).
enum class CheckerboardMode : uint8_t
{
    OFF,   // Every pixel.
    BLACK, // Pixels with (x + y + frameIndex) even.
    WHITE, // Pixels with (x + y + frameIndex) odd.
};

// REBLUR_* (document 004, REBLUR). Ranges in brackets; values outside get INVALID_ARGUMENT.
struct ReblurSettings
{
    HitDistanceParameters hitDistanceParameters = {};

    // Longest (slow) history in frames, [0, REBLUR_MAX_HISTORY_FRAME_NUM]. 0 = no temporal reuse.
    uint32_t maxAccumulatedFrameNum = 30;

    // Fast history (anti-lag reference) in frames, [0, maxAccumulatedFrameNum]. Where the slow
    // history leaves the fast one by more than antilagSigmaScale of its expected noise, the history
    // is shortened towards this length.
    uint32_t maxFastAccumulatedFrameNum = 6;

    // Histories shorter than this many frames are reconstructed from neighbours (history fix),
    // [0, REBLUR_MAX_HISTORY_FIX_FRAME_NUM]. 0 disables the history fix.
    uint32_t historyFixFrameNum = 3;

    // Pixel stride of the history fix's 5x5 sampling at history length 0, [1, 16].
    float historyFixStride = 3.0f;

    // Largest blur radius in pixels (short history, far hits, rough specular), [0, REBLUR_MAX_BLUR_RADIUS].
    float blurRadius = 24.0f;

    // Smallest blur radius in pixels once history is long (specular: times min(2 roughness, 1)),
    // [0, blurRadius]. The radius otherwise falls as blurRadius / (1 + history length); a floor
    // trades the last bit of noise for blur of thin features and contact shadows.
    float minBlurRadius = 0.0f;

    // Spatial pre-pass radius in pixels before temporal accumulation, per signal,
    // [0, REBLUR_MAX_BLUR_RADIUS]; 0 skips the pre-pass. Specular radiance: 4 filters the heavy-tailed
    // samples before the fast history and the anti-lag see them (static 64x64: relMSE -17%;
    // checkerboard input 1.27x the full-rate relMSE instead of 1.45x). Diffuse radiance: off (its
    // contact shadows and corners lose more to the blur than the noise it removes). The occlusion
    // variants (hit distance only, both signals): off (static 64x64 specular occlusion: ratio to the
    // input 16.7 without, 13.9 with a radius of 4).
    float diffusePrePassBlurRadius = 0.0f;
    float specularPrePassBlurRadius = 4.0f;
    float occlusionPrePassBlurRadius = 0.0f;

    // Post-blur radius relative to the blur radius, [0, 2].
    float postBlurRadiusScale = 0.5f;

    // Relative plane distance (fraction of viewZ) that drops a spatial weight to 0, (0, 1].
    float planeDistanceSensitivity = 0.02f;

    // Specular normal weight: accepted normal difference as a fraction of the lobe's half-angle, (0, 4].
    float lobeAngleFraction = 1.0f;

    // Specular roughness weight: accepted relative roughness difference, (0, 1].
    float roughnessFraction = 0.5f;

    // Anti-lag of the slow history: tolerated difference to the fast history in standard deviations
    // of the fast history's noise, [0.5, 64]. Lower reacts sooner to lighting changes, noisier.
    float antilagSigmaScale = 3.0f;

    // Temporal stabilization in frames, [0, REBLUR_MAX_HISTORY_FRAME_NUM]. 0 disables it.
    uint32_t maxStabilizedFrameNum = 12;

    // Roughness-based colour compression of the spatial passes, [0, 16]: radiance is filtered as
    // c / (1 + k * luminance) (k = this * (1 - roughness) for specular, this / 4 for diffuse), which
    // keeps single bright samples from smearing. 0 disables it.
    float colorCompression = 0.0f;

    // Anti-firefly: luminance above mean + antiFireflySigma * sigma of the 3x3 neighbours is
    // clamped before the blur, [0, 64]; 0 disables it.
    float antiFireflySigma = 0.0f;

    CheckerboardMode checkerboardMode = CheckerboardMode::OFF;

    // IN_DIFF_CONFIDENCE / IN_SPEC_CONFIDENCE are bound and shorten the history where < 1.
    bool isConfidenceInput = false;

    // Plain accumulation of the input without spatial filtering, clamping or anti-lag (up to
    // REBLUR_MAX_REFERENCE_FRAME_NUM frames): converges to the truth on a still view.
    bool forceReferenceAccumulation = false;
};

// REFLECTION (documents 000 and 002). Ranges in brackets; values outside get INVALID_ARGUMENT.
struct ReflectionSettings
{
    HitDistanceParameters hitDistanceParameters = {};

    // Pixels rougher than this are neither traced nor denoised (the application shades them
    // another way) and OUT_SPEC_RADIANCE_HITDIST is not written there, [0, 1].
    float roughnessThreshold = 1.0f;

    // Pixels smoother than this are mirrors: always traced, output as traced (no denoising), [0, 1].
    float mirrorRoughness = 0.0001f;

    // Base tracing rate: rays per 2x2 quad, 1, 2 or 4; the traced pixel(s) of a quad rotate with
    // frameIndex, and the others receive a copy of the quad's ray.
    uint32_t raysPerQuad = 1;

    // Pixels whose temporal variance (relative change of the output, written by the previous
    // frame) exceeds temporalVarianceThreshold trace a ray of their own, (0, 1].
    bool enableTemporalVarianceGuidedTracing = true;
    float temporalVarianceThreshold = 0.002f;

    // Longest history in frames, [1, REFLECTION_MAX_HISTORY_FRAME_NUM]; blend weight 1 / (n + 1).
    uint32_t maxHistoryFrameNum = 32;

    // Below this roughness the history follows the reflected image (hit reprojection by the hit
    // distance), above it the surface (motion vectors), [0, 1].
    float hitReprojectionRoughness = 0.3f;

    // History clip box: neighbourhood mean +- (historyClipSigma * sigma + historyClipLeeway * mean),
    // per channel; historyClipSigma [0.25, 16], historyClipLeeway [0, 4].
    float historyClipSigma = 1.0f;
    float historyClipLeeway = 0.1f;

    // Spatial edge stops: normal power [0, 4096], depth sigma (relative plane distance) (0, 64].
    float normalSigma = 512.0f;
    float depthSigma = 4.0f;

    // Passes that can be left out (for measurements): the spatial pass and the final blur.
    bool enableSpatial = true;
    bool enableBlur = true;
};

constexpr uint32_t REFLECTION_MAX_HISTORY_FRAME_NUM = 63;

constexpr uint32_t REBLUR_MAX_HISTORY_FRAME_NUM = 63;
constexpr uint32_t REBLUR_MAX_HISTORY_FIX_FRAME_NUM = 3;
constexpr uint32_t REBLUR_MAX_REFERENCE_FRAME_NUM = 255;
constexpr float REBLUR_MAX_BLUR_RADIUS = 64.0f;

// CONFIDENCE (document 003). Per pixel, with D and L the a-trous-filtered gradient texels
// (IN_GRADIENTS .x / .y for diffuse, .z / .w for specular; differences and luminances filtered
// independently, then interpolated to the pixel):
//     g = D / max(L, 1e-6)                                      normalized gradient, [0, 1] for the lab's
//     c = clamp(1 - (g - gradientThreshold) * sensitivity, 0, 1)    sensitivity: gradientSensitivity
//                                                                  (diffuse), specularGradientSensitivity
//     confidence = mix(c, history, c < history ? fallHistoryWeight : riseHistoryWeight)
//     confidence = confidence >= 0.99 ? 1 : confidence
// where 'history' is last frame's confidence reprojected with IN_MV (c alone after a restart or
// where the history falls off screen). One frame moves the confidence by at most
// (1 - historyWeight) * |c - history| (before the snap to 1, which keeps a rising confidence from
// stalling just below 1 in fp16 storage). Ranges in brackets; INVALID_ARGUMENT outside.
struct ConfidenceSettings
{
    // Normalized gradients up to this value are noise: confidence stays 1, [0, 1). 0.03 suits
    // gradients that re-shade the same light sample on both frames (exact up to fp16); noisier
    // gradients (a reservoir's sample that changed) want it higher (Shaders/Confidence/README.md).
    float gradientThreshold = 0.03f;

    // Slope of the diffuse confidence above the threshold: confidence reaches 0 at a normalized
    // gradient of gradientThreshold + 1 / gradientSensitivity, [1, 1000]. With 1, REBLUR's and
    // RELAX's diffuse error is no higher than without confidence on every lighting change of the scene
    // lab, and REBLUR_DIFFUSE no longer trails a switched light (Shaders/Confidence/README.md).
    float gradientSensitivity = 1.0f;

    // The same for the specular confidence, [1, 1000]. Steeper by default: a highlight narrower than
    // the 3x3 strata and the a-trous footprint has diluted gradients (2 lowers both specular
    // consumers' error and lets REBLUR_SPECULAR follow a switched light).
    float specularGradientSensitivity = 2.0f;

    // Weight of last frame's confidence where the new one is lower (history being invalidated),
    // [0, 1). 0: invalidation on the frame of the change.
    float fallHistoryWeight = 0.0f;

    // Weight of last frame's confidence where the new one is higher (history recovering), [0, 1).
    // Both weights default to 0 (no temporal filter): the scene lab's gradients are exact and its
    // first frame after a change is unbiased, and a confidence held below 1 on the frames after a
    // change keeps the consumers' histories short where a light toggles every few frames (RELAX
    // relMSE 1.7x with riseHistoryWeight 0.5 on toggling_light, Shaders/Confidence/README.md).
    // Applications whose lighting is biased right after a change (ReSTIR) raise them.
    float riseHistoryWeight = 0.0f;

    // A-trous passes over the gradients (3x3 kernel, steps 1, 2, 4, ...), [1, CONFIDENCE_MAX_ATROUS_PASS_NUM].
    // 4 covers 31 x 31 gradient texels (93 x 93 pixels).
    uint32_t atrousPassNum = 4;

    // Edge stopping of the a-trous passes (at the centre pixel of each stratum): a tap whose viewZ
    // differs from the centre's by this fraction of it or more has weight 0, [0, 1]; 0 turns depth
    // stopping off.
    float depthThreshold = 0.1f;

    // Normal weight max(n . n', 0)^normalPower, [0, 128]; 0 turns normal stopping off.
    float normalPower = 4.0f;

    // Local limit: a pixel's normalized gradient is at most that of the unfiltered strata within
    // this many strata of the four around it (2 r + 2 strata a side: 3 -> 8 x 8 strata, 24 x 24
    // pixels), so that the a-trous filter's 93 x 93 pixels do not cut the histories of a whole
    // region around a small change (a moving shadow), [0, CONFIDENCE_MAX_LOCAL_GRADIENT_RADIUS];
    // 0 turns it off (gradients too noisy per stratum to be read without the filter).
    uint32_t localGradientRadius = 3;
};

constexpr uint32_t CONFIDENCE_MAX_ATROUS_PASS_NUM = 5;
constexpr uint32_t CONFIDENCE_MAX_LOCAL_GRADIENT_RADIUS = 8;

// RELAX_DIFFUSE, RELAX_SPECULAR and RELAX_DIFFUSE_SPECULAR (one struct for both signals; fields
// prefixed diffuse / specular apply to one signal). Ranges in brackets; INVALID_ARGUMENT outside.
struct RelaxSettings
{
    // Normalization of the hit distances in IN_*_RADIANCE_HITDIST (.w); the output's .w is
    // normalized the same way.
    HitDistanceParameters hitDistanceParameters = {};

    // Slow history length in frames, [0, RELAX_MAX_HISTORY_FRAME_NUM]; 0 turns accumulation off.
    // Under motion: at most this over (1 + 20 * motion in pixels per frame), no fewer than the fast
    // history's frames (each resampling of a moving history blurs it).
    uint32_t diffuseMaxAccumulatedFrameNum = 30;
    uint32_t specularMaxAccumulatedFrameNum = 30;

    // Fast history length in frames, [0, the slow one]. The slow history is clamped to the fast
    // one's neighbourhood: shorter follows lighting changes faster and clamps harder.
    uint32_t diffuseMaxFastAccumulatedFrameNum = 4;
    uint32_t specularMaxFastAccumulatedFrameNum = 6;

    // Histories shorter than this many frames are rebuilt from their neighbours, [0, 3].
    uint32_t historyFixFrameNum = 3;

    // Distance between the history-fix taps at history length 0, pixels, [1, 32] (5x5 taps, so the
    // reach is this much on either side). Wider borrows light from other parts of the scene.
    float historyFixStride = 4.0f;

    // Slow history clamped to the fast history's 3x3 mean +- this many standard deviations, [0.5, 4]
    // (diffuse: the spread of the fast history; specular: the slow history's own spread and the fast
    // history's expected noise, see Shaders/Relax/README.md).
    float diffuseHistoryClampingColorBoxSigmaScale = 1.5f;
    float specularHistoryClampingColorBoxSigmaScale = 2.25f;

    // Anti-lag beyond the clamps: a 5x5 mean of this frame's input this many standard deviations
    // (of the difference of the means, plus 1% of the mean) from the same taps of the previous fast
    // history shortens both histories; so does a slow history this far from the pixel's fast
    // history. [0, 16], 0 (the default) turns it off: on the scene lab it cost still scenes
    // accuracy, and the mean clamps (diffuse) follow a light switch without it (see
    // Shaders/Relax/README.md).
    float antilagSigmaScale = 0.0f;

    // Histories shorter than this many frames take a 7x7 spatial variance, [0, RELAX_MAX_HISTORY_FRAME_NUM].
    uint32_t spatialVarianceEstimationHistoryThreshold = 3;

    // A-trous iterations (steps 1, 2, 4, ...), [2, 8]; the first reads from shared memory. A fifth
    // (step 16) changed no scene of the lab by more than 1% and cost 1 ms at 2560x1440 on an H100.
    uint32_t atrousIterationNum = 4;

    // Luminance stopper: a tap |dL| = phi * sigma(L) away weighs 1/e, (0, 16].
    float diffusePhiLuminance = 2.0f;
    float specularPhiLuminance = 1.0f;

    // Normal stopper: weight 0 beyond this fraction of the lobe half-angle atan(3 roughness^2)
    // (roughness 1 for diffuse) plus specularLobeAngleSlack, (0, 1].
    float diffuseLobeAngleFraction = 0.5f;
    float specularLobeAngleFraction = 0.5f;
    float specularLobeAngleSlack = 0.15f; // Degrees, [0, 90].

    // Roughness stopper (specular): weight 0 beyond |dr| = fraction * r + 0.01, (0, 1].
    float roughnessFraction = 0.15f;

    // Depth stopper: weight 0 beyond this distance to the centre's tangent plane, relative to
    // viewZ, (0, 1].
    float depthThreshold = 0.01f;

    CheckerboardMode checkerboardMode = CheckerboardMode::OFF;

    // Clamp the slow history's luminance to its 3x3 neighbours' range (removes fireflies).
    bool enableAntiFirefly = false;

    bool enableRoughnessEdgeStopping = true;

    // Read IN_DIFF_CONFIDENCE / IN_SPEC_CONFIDENCE (they must then be bound).
    bool useConfidenceInputs = false;
};

constexpr uint32_t RELAX_MAX_HISTORY_FRAME_NUM = 63;

} // namespace nrd
