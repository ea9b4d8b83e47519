// Constants every pass may embed at the start of its block with NRD_COMMON_CONSTANTS; read by
// GLSL (Bindings.glsl) and C++ (Source/PassDecl.h). The core fills them from CommonSettings
// (FrameContext::FillCommonConstants), so a pass only declares what is specific to it.
//
// "World" is camera-relative: the world's axes, the origin at the current frame's camera (so that
// positions keep their precision in float far from the world's origin).
// gViewToWorld       view -> world (current frame; its translation is 0)
// gWorldToClipPrev   world -> clip of the previous frame (reprojection)
// gWorldToViewPrev   world -> view of the previous frame (previous viewZ of a point)
// gViewToClip        view -> clip (current frame)
// gFrustum           view position from uv and viewZ: x = viewZ * (ndc.x * f.x + f.y), y = viewZ * (ndc.y * f.z + f.w)
// gMotionVectorScale .xyz = CommonSettings::motionVectorScale, .w = 1 for world-space motion
// gResourceSize      pixels processed this frame; gInvResourceSize = 1 / gResourceSize
// gProjectY          pixels per unit of (size / viewZ) at the image plane: 0.5 * height * |P11|
// gViewZSign         view-space z = viewZ * gViewZSign
// gDenoisingRange    |viewZ| beyond it is sky
// gDisocclusionThreshold relative depth tolerance of history reuse
// gFrameIndex        CommonSettings::frameIndex
// gResetHistory      1 on the first frame and whenever history must be discarded
#define NRD_COMMON_CONSTANTS                         \
    NRD_CONSTANT(mat4, gViewToWorld)                 \
    NRD_CONSTANT(mat4, gWorldToClipPrev)             \
    NRD_CONSTANT(mat4, gWorldToViewPrev)             \
    NRD_CONSTANT(mat4, gViewToClip)                  \
    NRD_CONSTANT(vec4, gFrustum)                     \
    NRD_CONSTANT(vec4, gMotionVectorScale)           \
    NRD_CONSTANT(uvec2, gResourceSize)               \
    NRD_CONSTANT(vec2, gInvResourceSize)             \
    NRD_CONSTANT(float, gProjectY)                   \
    NRD_CONSTANT(float, gViewZSign)                  \
    NRD_CONSTANT(float, gDenoisingRange)             \
    NRD_CONSTANT(float, gDisocclusionThreshold)      \
    NRD_CONSTANT(uint, gFrameIndex)                  \
    NRD_CONSTANT(uint, gResetHistory)                \
    NRD_CONSTANT(uint, gCommonPad0)                  \
    NRD_CONSTANT(uint, gCommonPad1)
