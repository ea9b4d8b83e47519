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
// deviation, then a Gaussian fall-off.
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

    // The 16 samples (mirrored by quad position, so the four pixels of a quad, which share rays,
    // sample apart) with their edge and similarity weights and world distances, and the closest hit
    // among the centre and the samples on its surface (edge weight above 1/2).
    ivec2 mirror = ivec2((pixel.x & 1) != 0 ? -1 : 1, (pixel.y & 1) != 0 ? -1 : 1);
    vec4 samples[16];
    float edgeWeights[16], similarityWeights[16], distances2[16]; // distances2: squared world distance
    float closestHit = center.w;
    for (uint i = 0u; i < 16u; i++)
    {
        ivec2 offset = HaltonOffset(i + 1u) * mirror;
        ivec2 p = pixel + offset;
        RfSurface s = _RF_LoadSurface(gIn_ViewZ, gIn_NormalRoughness, p);
        float we = 0.0;
        samples[i] = vec4(0.0);
        distances2[i] = 0.0;
        if (offset != ivec2(0) && s.needsDenoiser)
        {
            samples[i] = _RF_LoadRadiance(gIn_Radiance, p);
            vec3 Xs = _NRD_WorldPosition(_NRD_PixelUv(p), s.viewZ);
            we = _RF_EdgeWeight(c, Xc, s, Xs, gNormalSigma);
            distances2[i] = dot(Xs - Xc, Xs - Xc);
        }
        edgeWeights[i] = we;
        similarityWeights[i] = SimilarityWeight(_NRD_Luminance(samples[i].xyz), average);
        if (we > 0.5)
            closestHit = min(closestHit, samples[i].w);
    }

    // Gaussian of the world distance within the reflection's footprint. The closest hit sets it: an
    // average would be dominated by the far hits (misses) around a contact, which then blurs the sharp
    // reflection of the close object over it.
    float footprint = _RF_FootprintSigma(closestHit, c.viewZ, c.roughness, gHitDistParams);
    float inv2Sigma2 = 0.5 / (footprint * footprint);

    // Similarity-weighted sum, and the edge-weighted sum whose luminance the result keeps: the
    // similarity weights reject the samples unlike the tile, which are mostly the rare bright ones;
    // rescaling to the unrejected luminance keeps their energy (no darkening).
    float w0 = SimilarityWeight(_NRD_Luminance(center.xyz), average);
    vec4 sum = center * w0;
    float weightSum = w0;
    vec3 energySum = center.xyz;
    float energyWeightSum = 1.0;
    for (uint i = 0u; i < 16u; i++)
    {
        float we = edgeWeights[i] * exp(-distances2[i] * inv2Sigma2);
        float w = we * similarityWeights[i];
        sum += samples[i] * w;
        weightSum += w;
        energySum += samples[i].xyz * we;
        energyWeightSum += we;
    }
    vec4 result = weightSum > 1e-6 ? sum / weightSum : center;
    vec3 energy = energySum / energyWeightSum;
    float lumResult = _NRD_Luminance(result.xyz), lumEnergy = _NRD_Luminance(energy);
    result.xyz = lumResult > 1e-6 ? result.xyz * (lumEnergy / lumResult) : energy;
    imageStore(gOut_Spatial, pixel, _NRD_ClampToHalf(result));
}
