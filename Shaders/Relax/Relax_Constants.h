// RELAX: constants shared by every pass of the family (after NRD_COMMON_CONSTANTS). Read by GLSL and
// C++ through the pass declarations; Source/Relax.cpp fills them from RelaxSettings, per signal.
//
// gHitDistParams          HitDistanceParameters (A, B, C, D): normalized hit distance -> world units
// gMaxAccumulatedFrameNum slow history length in frames
// gMaxFastAccumulatedFrameNum fast history length in frames
// gHistoryFixFrameNum     histories shorter than this are reconstructed from neighbours
// gHistoryFixStride       distance between the history-fix taps, pixels, at history length 0
// gHistoryClampSigma      slow history clamped to fast mean +- this many standard deviations
// gAntilagSigma           a slow history beyond this many standard deviations of the fast one loses
//                         its length (anti-lag)
// gPhiLuminance           a-trous luminance stopper: |dL| / (gPhiLuminance * sigma(L))
// gLobeAngleFraction      a-trous normal stopper: part of the specular lobe half-angle (radians)
// gLobeAngleSlack         added to the normal stopper's angle (radians)
// gRoughnessFraction      a-trous roughness stopper: |dr| / (gRoughnessFraction * r + 0.01)
// gDepthThreshold         a-trous depth stopper: plane distance relative to viewZ
// gVarianceHistoryThreshold histories shorter than this take a 7x7 spatial variance
// gAtrousStep             pixels between a-trous taps (one dispatch per iteration)
// gFlags                  RELAX_FLAG_* below
// gCheckerboard           0: every pixel traced; 1 / 2: pixels with (x + y + frameIndex + gCheckerboard) even traced
//                         (CheckerboardMode::BLACK = 2, WHITE = 1)
#define RELAX_CONSTANTS                                 \
    NRD_CONSTANT(vec4, gHitDistParams)                  \
    NRD_CONSTANT(float, gMaxAccumulatedFrameNum)        \
    NRD_CONSTANT(float, gMaxFastAccumulatedFrameNum)    \
    NRD_CONSTANT(float, gHistoryFixFrameNum)            \
    NRD_CONSTANT(float, gHistoryFixStride)              \
    NRD_CONSTANT(float, gHistoryClampSigma)             \
    NRD_CONSTANT(float, gAntilagSigma)                  \
    NRD_CONSTANT(float, gPhiLuminance)                  \
    NRD_CONSTANT(float, gLobeAngleFraction)             \
    NRD_CONSTANT(float, gLobeAngleSlack)                \
    NRD_CONSTANT(float, gRoughnessFraction)             \
    NRD_CONSTANT(float, gDepthThreshold)                \
    NRD_CONSTANT(float, gVarianceHistoryThreshold)      \
    NRD_CONSTANT(uint, gAtrousStep)                     \
    NRD_CONSTANT(uint, gFlags)                          \
    NRD_CONSTANT(uint, gCheckerboard)                   \
    NRD_CONSTANT(uint, gRelaxPad0)

#define RELAX_FLAG_ANTI_FIREFLY 1u       // History fix pass: clamp fireflies to the 3x3 neighbourhood.
#define RELAX_FLAG_WRITE_VIEWZ 2u        // History fix pass: store viewZ for the next frame.
#define RELAX_FLAG_LAST_ATROUS 4u        // A-trous: write the output (radiance, hit distance).
#define RELAX_FLAG_ROUGHNESS_STOP 8u     // A-trous: roughness stopper on.
#define RELAX_FLAG_CONFIDENCE 16u        // Temporal accumulation: confidence input bound.
