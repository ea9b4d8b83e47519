// REBLUR: constants after NRD_COMMON_CONSTANTS in every pass's block (read by GLSL and C++).
//
// gHitDistParams          HitDistanceParameters (A, B, C, D): normalization of hit distances
// gMaxAccumulatedFrameNum longest (slow) history in frames
// gMaxFastAccumulatedFrameNum longest fast history in frames (anti-lag reference)
// gHistoryFixFrameNum     histories shorter than this are reconstructed from neighbours
// gHistoryFixStride       pixel stride of the history-fix sampling at history length 0
// gBlurRadius             largest blur radius in pixels (history length 0, far hits, rough)
// gMinBlurRadius          smallest blur radius in pixels (long history)
// gPassRadiusScale        radius multiplier of this dispatch (pre-pass / blur / post-blur)
// gPlaneDistanceSensitivity relative plane distance that drops a spatial weight to 0
// gLobeAngleFraction      part of the specular lobe half-angle accepted by the normal weight
// gRoughnessFraction      relative roughness difference that drops a spatial weight to 0
// gAntilagSigmaScale      slow-vs-fast history difference (in standard deviations) tolerated
// gStabilizationFrameNum  temporal stabilization length in frames (0 = off)
// gColorCompression       strength of the roughness-based colour compression of the spatial passes
// gFireflyScale           anti-firefly: luminance above mean + this * sigma of the neighbours is clamped (0 = off)
// gPassIndex              Reblur_Blur: 0 pre-pass, 1 blur, 2 post-blur
// gFlags                  REBLUR_FLAG_* below
// gCheckerboard           0 full-rate input, else 1 + the parity of the pixels traced this frame
#ifndef REBLUR_CONSTANTS_H
#define REBLUR_CONSTANTS_H
#define REBLUR_CONSTANTS                                \
    NRD_CONSTANT(vec4, gHitDistParams)                  \
    NRD_CONSTANT(float, gMaxAccumulatedFrameNum)        \
    NRD_CONSTANT(float, gMaxFastAccumulatedFrameNum)    \
    NRD_CONSTANT(float, gHistoryFixFrameNum)            \
    NRD_CONSTANT(float, gHistoryFixStride)              \
    NRD_CONSTANT(float, gBlurRadius)                    \
    NRD_CONSTANT(float, gMinBlurRadius)                 \
    NRD_CONSTANT(float, gPassRadiusScale)               \
    NRD_CONSTANT(float, gPlaneDistanceSensitivity)      \
    NRD_CONSTANT(float, gLobeAngleFraction)             \
    NRD_CONSTANT(float, gRoughnessFraction)             \
    NRD_CONSTANT(float, gAntilagSigmaScale)             \
    NRD_CONSTANT(float, gStabilizationFrameNum)         \
    NRD_CONSTANT(float, gColorCompression)              \
    NRD_CONSTANT(float, gFireflyScale)                  \
    NRD_CONSTANT(uint, gPassIndex)                      \
    NRD_CONSTANT(uint, gFlags)                          \
    NRD_CONSTANT(uint, gCheckerboard)                   \
    NRD_CONSTANT(uint, gReblurPad0)                     \
    NRD_CONSTANT(uint, gReblurPad1)                     \
    NRD_CONSTANT(uint, gReblurPad2)

#define REBLUR_FLAG_PREPASS 1u          // The pre-pass ran: the temporal pass reads its output.
#define REBLUR_FLAG_REFERENCE 2u        // forceReferenceAccumulation: no spatial filtering, no clamping.
#define REBLUR_FLAG_CONFIDENCE 4u       // IN_*_CONFIDENCE is bound.

// Tile size of the classification (sky tiles are skipped by every later pass).
#define REBLUR_TILE_SIZE 16

#endif
