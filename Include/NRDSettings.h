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
// uv = (ndc.xy * 0.5 + 0.5) addresses the texture with v growing downwards.
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

// SIGMA_SHADOW and SIGMA_SHADOW_TRANSLUCENCY.
struct SigmaSettings
{
    // Direction towards an infinite light (world space, need not be normalized). Used to orient
    // the anisotropic penumbra blur; {0, 0, 0} means "unknown" (isotropic blur).
    float lightDirection[3] = {0.0f, 0.0f, 0.0f};

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

} // namespace nrd
