#version 450
#extension GL_GOOGLE_include_directive : require

// REFLECTION reprojection (document 002, "reproject"). One 8x8 group per listed tile.

#define REFLECTION_DENOISE_PASS
#include "Bindings.glsl"
#include "Reflection_Constants.h"
#include "Reflection_Reproject.resources.h"
#include "CommonFrame.glsl"
#include "Reflection_Common.glsl"

shared vec4 sSum[64]; // rgb, count
shared vec2 sLum[64]; // luminance, luminance^2

void main()
{
    uint index = gl_LocalInvocationIndex;
    uvec2 tile = _RF_UnpackTile(gTileList[gl_WorkGroupID.x]);
    ivec2 pixel = ivec2(_RF_TilePixel(gTileList[gl_WorkGroupID.x]));
    RfSurface c = _RF_LoadSurface(gIn_ViewZ, gIn_NormalRoughness, pixel);
    vec4 radiance = c.isInside ? _RF_LoadRadiance(gIn_Radiance, pixel) : vec4(0.0);

    if (c.isMirror)
        imageStore(gOut_Output, pixel, radiance);

    // 8x8 average and luminance variance of the pixels that need the denoiser.
    float lum = _NRD_Luminance(radiance.xyz);
    sSum[index] = c.needsDenoiser ? vec4(radiance.xyz, 1.0) : vec4(0.0);
    sLum[index] = c.needsDenoiser ? vec2(lum, lum * lum) : vec2(0.0);
    barrier();
    for (uint stride = 32u; stride > 0u; stride >>= 1u)
    {
        if (index < stride)
        {
            sSum[index] += sSum[index + stride];
            sLum[index] += sLum[index + stride];
        }
        barrier();
    }
    if (index == 0u)
    {
        float n = sSum[0].w;
        vec3 mean = n > 0.0 ? sSum[0].xyz / n : vec3(0.0);
        vec2 m = n > 0.0 ? sLum[0] / n : vec2(0.0);
        imageStore(gOut_TileAverage, ivec2(tile), _NRD_ClampToHalf(vec4(mean, max(m.y - m.x * m.x, 0.0))));
    }

    if (!c.needsDenoiser)
        return;

    // Surface and hit reprojection (the reflection moves with its virtual image on shiny surfaces).
    vec2 uv = _NRD_PixelUv(pixel);
    vec3 X = _NRD_WorldPosition(uv, c.viewZ);
    vec3 mv = texelFetch(sampler2D(gIn_Mv, gNearestClamp), pixel, 0).xyz;
    vec3 Xprev;
    vec2 uvPrev = _NRD_PreviousUv(uv, X, mv, Xprev);
    float expectedViewZ = _NRD_PreviousViewZ(Xprev);
    if (c.roughness < gHitReprojectionRoughness)
    {
        float hitDist = _NRD_GetHitDist(radiance.w, c.viewZ, gHitDistParams, c.roughness);
        vec2 uvVirtual = _NRD_VirtualPreviousUv(X, Xprev - X, _NRD_CameraPosition(), hitDist, c.roughness, gWorldToClipPrev);
        // The virtual image only holds where it lands on the same surface.
        if (_NRD_IsInScreen(uvVirtual))
            uvPrev = uvVirtual;
    }

    ivec2 size = ivec2(gResourceSize);
    vec3 V = normalize(_NRD_CameraPosition() - X);
    float tolerance = _NRD_DisocclusionTolerance(c.viewZ, expectedViewZ, abs(dot(c.N, V)), gDisocclusionThreshold, gProjectY);
    NrdFootprint fp = _NRD_Footprint(uvPrev, vec2(size));
    vec4 prevViewZ = _NRD_GatherFootprint(gIn_PrevViewZ, fp.origin, size);
    // Hit reprojection lands on another point of the surface than X: a wider depth tolerance, the
    // normal and roughness tests below keep it on the same surface.
    NrdReprojection r = _NRD_Reprojection(uvPrev, size, prevViewZ, expectedViewZ, tolerance * 4.0);
    // Normal and roughness history (2x2 slow path: each tap on its own).
    vec4 weights = r.weights;
    for (int k = 0; k < 4; k++)
    {
        if (weights[k] <= 0.0)
            continue;
        vec4 prevNr = texelFetch(sampler2D(gIn_PrevNormalRoughness, gNearestClamp), r.footprint.origin + ivec2(k & 1, k >> 1), 0);
        bool isSame = dot(prevNr.xyz, c.N) > 0.9 && abs(prevNr.w - c.roughness) < 0.05 + 0.1 * c.roughness;
        weights[k] = isSame ? weights[k] : 0.0;
    }
    r.weights = weights;
    r.footprintWeight = dot(weights, vec4(1.0));
    bool isHistoryValid = (gFlags & REFLECTION_FLAG_HISTORY_VALID) != 0u && r.footprintWeight > 0.05;
    vec4 history = isHistoryValid ? _NRD_BilinearHistory(gIn_History, r) : vec4(0.0);
    float samples = isHistoryValid ? clamp(history.w, 0.0, gMaxHistoryFrameNum) : 0.0;
    imageStore(gOut_Reprojected, pixel, _NRD_ClampToHalf(vec4(max(history.xyz, vec3(0.0)), samples)));
}
