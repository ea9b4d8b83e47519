// CONFIDENCE temporal pass (document 003: "normalized, i.e. luminance differences are divided by
// the absolute luminance values, and then converted into (0-1) confidence using a simple function
// ... a short-history temporal filter"). The filtered gradients are interpolated bilinearly
// between stratum centres (difference and luminance separately), normalized and converted
// (_Confidence_FromGradient); the result is blended with last frame's confidence at the
// reprojected position, with one weight while confidence falls and another while it rises, so an
// invalidation spreads over a few frames instead of resetting the history on one.
#version 450
#extension GL_GOOGLE_include_directive : require

#include "Bindings.glsl"
#include "Confidence_Temporal.resources.h"
#include "CommonFrame.glsl"
#include "Confidence_Common.glsl"

void main()
{
    ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(uvec2(pixel), gResourceSize)))
        return;
    float viewZ = texelFetch(sampler2D(gIn_ViewZ, gNearestClamp), pixel, 0).x;
    if (_NRD_IsSky(viewZ))
    {
        // Not written; the history restarts at 1 should a surface appear here.
        imageStore(gOut_History, pixel, vec4(1.0));
        return;
    }

    // Stratum centres sit at pixel 3x + 1.5 (in pixel units): bilinear weights between them.
    vec2 f = (vec2(pixel) + 0.5) / 3.0 - 0.5;
    ivec2 origin = ivec2(floor(f));
    vec4 w = _NRD_BilinearWeights(f - vec2(origin));
    ivec2 maxTexel = ivec2(gGradientSize) - 1;
    vec4 g = w.x * _Confidence_LoadGradient(gIn_Gradients, clamp(origin, ivec2(0), maxTexel)) +
             w.y * _Confidence_LoadGradient(gIn_Gradients, clamp(origin + ivec2(1, 0), ivec2(0), maxTexel)) +
             w.z * _Confidence_LoadGradient(gIn_Gradients, clamp(origin + ivec2(0, 1), ivec2(0), maxTexel)) +
             w.w * _Confidence_LoadGradient(gIn_Gradients, clamp(origin + ivec2(1, 1), ivec2(0), maxTexel));
    // Local limit (gLocalRadius > 0): the normalized gradient is at most that of the unfiltered
    // strata near the pixel, the means over (2 r + 1)^2 strata (Confidence_Local) interpolated as
    // above. The a-trous filter spreads a change over 93 x 93 pixels, and on a surface where the
    // change's sum of differences over the sum of luminances stays above the threshold (a moving
    // shadow across a row of floor) every history of that region was cut where only a few strata
    // changed (fast_occluder; Shaders/Confidence/README.md, "The local limit").
    if (gLocalRadius != 0u)
    {
        vec4 local = w.x * texelFetch(sampler2D(gIn_Local, gNearestClamp), clamp(origin, ivec2(0), maxTexel), 0) +
                     w.y * texelFetch(sampler2D(gIn_Local, gNearestClamp), clamp(origin + ivec2(1, 0), ivec2(0), maxTexel), 0) +
                     w.z * texelFetch(sampler2D(gIn_Local, gNearestClamp), clamp(origin + ivec2(0, 1), ivec2(0), maxTexel), 0) +
                     w.w * texelFetch(sampler2D(gIn_Local, gNearestClamp), clamp(origin + ivec2(1, 1), ivec2(0), maxTexel), 0);
        // Each signal takes the smaller normalized gradient (difference and luminance as a pair).
        if (local.x * max(g.y, 1e-6) < g.x * max(local.y, 1e-6))
            g.xy = local.xy;
        if (local.z * max(g.w, 1e-6) < g.z * max(local.w, 1e-6))
            g.zw = local.zw;
    }
    vec2 confidence = vec2(_Confidence_FromGradient(g.x, g.y, gGradientThreshold, gGradientSensitivity),
                           _Confidence_FromGradient(g.z, g.w, gGradientThreshold, gSpecularGradientSensitivity));

    if (gResetHistory == 0u)
    {
        // Last frame's confidence where this surface was (nearest texel: a still view reads back
        // exactly what it wrote, so confidence 1 stays exactly 1).
        vec2 uv = _NRD_PixelUv(pixel);
        vec3 worldPosPrev;
        vec3 mv = texelFetch(sampler2D(gIn_Mv, gNearestClamp), pixel, 0).xyz;
        vec2 uvPrev = _NRD_PreviousUv(uv, _NRD_WorldPosition(uv, viewZ), mv, worldPosPrev);
        if (_NRD_IsInScreen(uvPrev))
        {
            ivec2 prevPixel = min(ivec2(uvPrev * vec2(gResourceSize)), ivec2(gResourceSize) - 1);
            vec2 history = texelFetch(sampler2D(gIn_History, gNearestClamp), prevPixel, 0).xy;
            history = clamp(vec2(_NRD_Sanitize(history.x, 1.0), _NRD_Sanitize(history.y, 1.0)), vec2(0.0), vec2(1.0));
            vec2 weight = mix(vec2(gRiseHistoryWeight), vec2(gFallHistoryWeight), lessThan(confidence, history));
            confidence = mix(confidence, history, weight);
        }
    }
    // A rising confidence ends at exactly 1: fp16 history storage (rounded towards 0 on some
    // devices) would otherwise leave it just below 1 for good, and consumers shorten their history
    // for anything below 1.
    confidence = mix(confidence, vec2(1.0), greaterThanEqual(confidence, vec2(CONFIDENCE_SNAP_TO_ONE)));

    imageStore(gOut_History, pixel, vec4(confidence, 0.0, 0.0));
    imageStore(gOut_DiffConfidence, pixel, vec4(confidence.x));
    imageStore(gOut_SpecConfidence, pixel, vec4(confidence.y));
}
