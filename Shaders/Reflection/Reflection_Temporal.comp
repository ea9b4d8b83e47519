#version 450
#extension GL_GOOGLE_include_directive : require

// REFLECTION temporal pass (document 002, "resolve temporal"). One 8x8 group per listed tile.

#define REFLECTION_DENOISE_PASS
#include "Bindings.glsl"
#include "Reflection_Constants.h"
#include "Reflection_Temporal.resources.h"
#include "CommonFrame.glsl"
#include "Reflection_Common.glsl"

void main()
{
    ivec2 pixel = ivec2(_RF_TilePixel(gTileList[gl_WorkGroupID.x]));
    RfSurface c = _RF_LoadSurface(gIn_ViewZ, gIn_NormalRoughness, pixel);
    if (!c.needsDenoiser)
        return;
    vec4 current = _RF_LoadRadiance(gIn_Spatial, pixel);
    vec3 Xc = _NRD_WorldPosition(_NRD_PixelUv(pixel), c.viewZ);

    // Gaussian-weighted 5x5 neighbourhood statistics of the spatial result on the same surface.
    const float kGauss[3] = float[3](1.0, 0.6065, 0.1353);
    vec3 m1 = vec3(0.0), m2 = vec3(0.0);
    float weightSum = 0.0;
    for (int y = -2; y <= 2; y++)
    {
        for (int x = -2; x <= 2; x++)
        {
            ivec2 p = pixel + ivec2(x, y);
            RfSurface s = _RF_LoadSurface(gIn_ViewZ, gIn_NormalRoughness, p);
            float w = kGauss[abs(x)] * kGauss[abs(y)];
            if (x != 0 || y != 0)
                w *= _RF_EdgeWeight(c, Xc, s, _NRD_WorldPosition(_NRD_PixelUv(p), s.viewZ), 32.0);
            if (w <= 0.0)
                continue;
            vec3 v = x == 0 && y == 0 ? current.xyz : _RF_LoadRadiance(gIn_Spatial, p).xyz;
            m1 += v * w;
            m2 += v * v * w;
            weightSum += w;
        }
    }
    vec3 mean = m1 / weightSum;
    vec3 sigma = sqrt(max(m2 / weightSum - mean * mean, vec3(0.0)));

    // Outlier removal: the current value stays within 3 sigma of its neighbourhood.
    current.xyz = clamp(current.xyz, max(mean - 3.0 * sigma, vec3(0.0)), mean + 3.0 * sigma);

    vec4 reprojected = _NRD_Sanitize(texelFetch(sampler2D(gIn_Reprojected, gNearestClamp), pixel, 0), 0.0);
    float samples = clamp(reprojected.w, 0.0, gMaxHistoryFrameNum);
    vec3 history = max(reprojected.xyz, vec3(0.0));
    // History clip: neighbourhood box with leeway. Clamping to the box itself darkens: the noise of a
    // reflection is skewed (rare bright samples), so the neighbourhood's mean and sigma are most often
    // below the converged history. A history outside the box is shortened instead, by how far it lies
    // outside (in box half-sizes, on luminance), and clamped only to a box three times as wide.
    vec3 halfSize = gHistoryClipSigma * sigma + gHistoryClipLeeway * mean;
    float lumHalfSize = _NRD_Luminance(halfSize) + 1e-6;
    float outside = max(abs(_NRD_Luminance(history) - _NRD_Luminance(mean)) - lumHalfSize, 0.0) / lumHalfSize;
    samples /= 1.0 + 4.0 * outside * outside;
    history = clamp(history, mean - 3.0 * halfSize, mean + 3.0 * halfSize);

    float newSamples = min(samples + 1.0, gMaxHistoryFrameNum);
    vec3 result = samples > 0.0 ? mix(history, current.xyz, 1.0 / newSamples) : current.xyz;

    // Temporal variance for the next frame's tracing decision: the relative change this frame made
    // to the history (1 without history).
    float lumNew = _NRD_Luminance(result), lumOld = _NRD_Luminance(history);
    float change = (lumNew - lumOld) / max(lumNew + lumOld, 1e-4);
    float variance = samples > 0.0 ? change * change : 1.0;

    vec4 outValue = _NRD_ClampToHalf(vec4(result, current.w));
    imageStore(gOut_History, pixel, vec4(outValue.xyz, newSamples));
    imageStore(gOut_TemporalVariance, pixel, vec4(variance));
    imageStore(gOut_Temporal, pixel, outValue);
    if ((gFlags & REFLECTION_FLAG_BLUR) == 0u)
        imageStore(gOut_Output, pixel, outValue);
}
