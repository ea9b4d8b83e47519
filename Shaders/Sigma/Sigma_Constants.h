// SIGMA: constants shared by every pass of the method (after NRD_COMMON_CONSTANTS). Read by GLSL and
// C++ through the pass declarations; Source/Sigma.cpp fills them from SigmaSettings.
//
// gLightDirectionView     .xyz direction towards an infinite light in view space (normalized),
//                         .w = 1 if known (anisotropic kernel), 0 otherwise
// gBlurRadiusScale        kernel radius in pixels per pixel of penumbra radius
// gPlaneDistanceSensitivity  plane distance tolerance relative to viewZ
// gMaxStabilizedFrameNum  temporal stabilization length in frames
// gShadowMotionPerPenumbra, gLightPositionView, gLightMotionView: the light's move since the previous
//                         frame; gOccluderLightView: where an infinite light's occluders lie
//                         (Shaders/Include/ShadowMotion.glsl, Source/ShadowLightMotion.h)
#ifndef SIGMA_TRANSLUCENCY
#define SIGMA_TRANSLUCENCY 0
#endif

#define SIGMA_CONSTANTS                              \
    NRD_CONSTANT(vec4, gLightDirectionView)          \
    NRD_CONSTANT(float, gBlurRadiusScale)            \
    NRD_CONSTANT(float, gPlaneDistanceSensitivity)   \
    NRD_CONSTANT(float, gMaxStabilizedFrameNum)      \
    NRD_CONSTANT(float, gShadowMotionPerPenumbra)    \
    NRD_CONSTANT(vec4, gLightPositionView)           \
    NRD_CONSTANT(vec4, gLightMotionView)             \
    NRD_CONSTANT(vec4, gOccluderLightView)
