// SIGMA: constants shared by every pass of the method (after NRD_COMMON_CONSTANTS). Read by GLSL and
// C++ through the pass declarations; Source/Sigma.cpp fills them from SigmaSettings.
//
// gLightDirectionView     .xyz direction towards an infinite light in view space (normalized),
//                         .w = 1 if known (anisotropic kernel), 0 otherwise
// gBlurRadiusScale        kernel radius in pixels per pixel of penumbra radius
// gPlaneDistanceSensitivity  plane distance tolerance relative to viewZ
// gMaxStabilizedFrameNum  temporal stabilization length in frames
// gShadowMotionPerPenumbra  how far the light's turn since the previous frame moved a shadow, in its
//                         penumbra radii (0: unknown or none)
// gLightPositionView      .xyz a sphere light's position in view space, .w 1 / its radius (0: none)
// gLightMotionView        .xyz its displacement since the previous frame (world, rotated into view
//                         space), .w 1 with a sphere light that moved, 0 otherwise
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
    NRD_CONSTANT(vec4, gLightMotionView)
