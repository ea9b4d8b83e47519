// REFLECTION constants shared by the shaders and Source/Reflection.cpp.
#define REFLECTION_TILE_SIZE 8
#define REFLECTION_RAYS_PER_GROUP 64
#define REFLECTION_COUNTERS_WORDS 16
#define REFLECTION_FLAG_GUIDED_TRACING 1
#define REFLECTION_FLAG_HISTORY_VALID 2
#define REFLECTION_FLAG_SPATIAL 4
#define REFLECTION_FLAG_BLUR 8

// Constant block of the denoising passes (after NRD_COMMON_CONSTANTS), one layout for all of them.
#define REFLECTION_DENOISE_CONSTANTS                  \
    NRD_CONSTANT(vec4, gHitDistParams)                \
    NRD_CONSTANT(float, gMirrorRoughness)             \
    NRD_CONSTANT(float, gRoughnessThreshold)          \
    NRD_CONSTANT(float, gHitReprojectionRoughness)    \
    NRD_CONSTANT(float, gMaxHistoryFrameNum)          \
    NRD_CONSTANT(float, gHistoryClipSigma)            \
    NRD_CONSTANT(float, gHistoryClipLeeway)           \
    NRD_CONSTANT(float, gNormalSigma)                 \
    NRD_CONSTANT(float, gDepthSigma)                  \
    NRD_CONSTANT(uint, gFlags)                        \
    NRD_CONSTANT(uint, gDenoisePad0)                  \
    NRD_CONSTANT(uint, gDenoisePad1)                  \
    NRD_CONSTANT(uint, gDenoisePad2)
