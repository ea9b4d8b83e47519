// Helpers that read the common constants: include after the pass's .resources.h, whose constant
// block must start with NRD_COMMON_CONSTANTS.
#ifndef NRD_COMMON_FRAME_GLSL
#define NRD_COMMON_FRAME_GLSL

#include "Common.glsl"
#include "Reprojection.glsl"

bool _NRD_IsSky(float viewZ) { return !_NRD_IsFinite(viewZ) || abs(viewZ) > gDenoisingRange || viewZ <= 0.0; }

vec3 _NRD_ViewPosition(vec2 uv, float viewZ)
{
    vec2 ndc = uv * 2.0 - 1.0;
    return vec3(viewZ * (ndc.x * gFrustum.x + gFrustum.y), viewZ * (ndc.y * gFrustum.z + gFrustum.w), viewZ * gViewZSign);
}

vec3 _NRD_WorldPosition(vec2 uv, float viewZ) { return (gViewToWorld * vec4(_NRD_ViewPosition(uv, viewZ), 1.0)).xyz; }

vec2 _NRD_PixelUv(ivec2 pixel) { return (vec2(pixel) + 0.5) * gInvResourceSize; }

// Previous-frame uv of a surface point, from IN_MV and the matrices (see CommonSettings).
// 'worldPosPrev' receives the point's previous world position (for the disocclusion test).
vec2 _NRD_PreviousUv(vec2 uv, vec3 worldPos, vec3 mv, out vec3 worldPosPrev)
{
    vec3 scale = gMotionVectorScale.xyz;
    worldPosPrev = worldPos;
    if (gMotionVectorScale.w != 0.0)
        worldPosPrev = worldPos + _NRD_Sanitize(mv, 0.0) * scale;
    else if (scale.x != 0.0 || scale.y != 0.0)
    {
        // 2D motion: the surface moved on screen; its previous world position is unknown, keep the
        // current one for the depth test (objects moving along the view axis then disocclude).
        vec2 uvPrev = uv + _NRD_Sanitize(mv, 0.0).xy * scale.xy;
        return uvPrev;
    }
    vec4 clip = gWorldToClipPrev * vec4(worldPosPrev, 1.0);
    if (clip.w <= NRD_EPS)
        return vec2(-1.0); // Behind the previous camera: off screen.
    return (clip.xy / clip.w) * 0.5 + 0.5;
}

// Pixels between 'uvPrev' (_NRD_PreviousUv's) and where the camera's motion alone takes world position
// 'worldPos': the surface's own motion on screen, 0 on a still object (and without motion vectors).
float _NRD_ObjectMotionPixels(vec2 uvPrev, vec3 worldPos)
{
    vec4 clip = gWorldToClipPrev * vec4(worldPos, 1.0);
    vec2 uvCamera = clip.w > NRD_EPS ? (clip.xy / clip.w) * 0.5 + 0.5 : vec2(-1.0);
    vec2 pixels = abs(uvPrev - uvCamera) * vec2(gResourceSize);
    return max(pixels.x, pixels.y);
}

// Previous viewZ of a world position (for comparison with the previous viewZ texture).
float _NRD_PreviousViewZ(vec3 worldPosPrev) { return (gWorldToViewPrev * vec4(worldPosPrev, 1.0)).z * gViewZSign; }

// World-space camera position of the current frame.
vec3 _NRD_CameraPosition() { return gViewToWorld[3].xyz; }

bool _NRD_IsInScreen(vec2 uv) { return all(greaterThanEqual(uv, vec2(0.0))) && all(lessThan(uv, vec2(1.0))); }

#endif
