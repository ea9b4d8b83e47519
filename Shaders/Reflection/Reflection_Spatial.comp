#version 450
#extension GL_GOOGLE_include_directive : require

// REFLECTION spatial pass (document 002, "prefilter"). One 8x8 group per listed tile.

#define REFLECTION_DENOISE_PASS
#include "Bindings.glsl"
#include "Reflection_Constants.h"
#include "Reflection_Spatial.resources.h"
#include "CommonFrame.glsl"
#include "Reflection_Common.glsl"

float RadicalInverse(uint i, uint base)
{
    float result = 0.0, f = 1.0 / float(base);
    for (uint n = i; n > 0u; n /= base)
    {
        result += f * float(n % base);
        f /= float(base);
    }
    return result;
}

// Halton(2, 3) point 'i' (from 1) discretized to the 7x7 window around the pixel.
ivec2 HaltonOffset(uint i) { return ivec2(floor(vec2(RadicalInverse(i, 2u), RadicalInverse(i, 3u)) * 7.0)) - 3; }

// Weight of a sample by how close its luminance is to the tile's average: 1 within one standard
// deviation, then a Gaussian fall-off (keeps single bright samples from spreading).
float SimilarityWeight(float lum, vec4 average)
{
    float mean = _NRD_Luminance(average.xyz);
    float sigma = sqrt(max(average.w, 0.0)) + 1e-3 * mean + 1e-6;
    float z = max(abs(lum - mean) / sigma - 1.0, 0.0);
    return exp(-0.5 * z * z);
}

void main()
{
    uvec2 tile = _RF_UnpackTile(gTileList[gl_WorkGroupID.x]);
    ivec2 pixel = ivec2(_RF_TilePixel(gTileList[gl_WorkGroupID.x]));
    RfSurface c = _RF_LoadSurface(gIn_ViewZ, gIn_NormalRoughness, pixel);
    if (!c.needsDenoiser)
        return;
    vec4 center = _RF_LoadRadiance(gIn_Radiance, pixel);
    if ((gFlags & REFLECTION_FLAG_SPATIAL) == 0u)
    {
        imageStore(gOut_Spatial, pixel, center);
        return;
    }
    vec4 average = _NRD_Sanitize(texelFetch(sampler2D(gIn_TileAverage, gNearestClamp), ivec2(tile), 0), 0.0);
    vec3 Xc = _NRD_WorldPosition(_NRD_PixelUv(pixel), c.viewZ);

    float w0 = SimilarityWeight(_NRD_Luminance(center.xyz), average);
    vec4 sum = center * w0;
    float weightSum = w0;
    // Mirrored by quad position, so the four pixels of a quad (which share rays) sample apart.
    ivec2 mirror = ivec2((pixel.x & 1) != 0 ? -1 : 1, (pixel.y & 1) != 0 ? -1 : 1);
    for (uint i = 1u; i <= 16u; i++)
    {
        ivec2 offset = HaltonOffset(i) * mirror;
        if (offset == ivec2(0))
            continue;
        ivec2 p = pixel + offset;
        RfSurface s = _RF_LoadSurface(gIn_ViewZ, gIn_NormalRoughness, p);
        if (!s.needsDenoiser)
            continue;
        vec3 Xs = _NRD_WorldPosition(_NRD_PixelUv(p), s.viewZ);
        vec4 v = _RF_LoadRadiance(gIn_Radiance, p);
        float w = _RF_EdgeWeight(c, Xc, s, Xs, gNormalSigma) * SimilarityWeight(_NRD_Luminance(v.xyz), average);
        sum += v * w;
        weightSum += w;
    }
    vec4 result = weightSum > 1e-6 ? sum / weightSum : center;
    imageStore(gOut_Spatial, pixel, _NRD_ClampToHalf(result));
}
