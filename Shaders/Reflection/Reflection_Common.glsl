// REFLECTION: what several passes share. Tests/ReflectionTests.cpp evaluates the same per-pixel
// rules on the CPU (keep both in step).
#ifndef REFLECTION_COMMON_GLSL
#define REFLECTION_COMMON_GLSL

#include "Reflection_Constants.h"

// Words of the counters buffer (BufferContent::RAY_COUNTERS in NRDDescs.h).
#define RF_WORD_TRACE_ARGS 0u
#define RF_WORD_RAY_COUNT 3u
#define RF_WORD_DENOISE_ARGS 4u
#define RF_WORD_TILE_COUNT 7u
#define RF_WORD_LIVE_RAYS 8u
#define RF_WORD_LIVE_TILES 9u

// Ray list entry: x | y << 14 | copy bits (horizontal, vertical, diagonal quad neighbour).
#define RF_COPY_HORIZONTAL (1u << 28u)
#define RF_COPY_VERTICAL (1u << 29u)
#define RF_COPY_DIAGONAL (1u << 30u)

uint _RF_PackRay(uvec2 pixel, bool copyH, bool copyV, bool copyD)
{
    return (pixel.x & 0x3FFFu) | ((pixel.y & 0x3FFFu) << 14u) | (copyH ? RF_COPY_HORIZONTAL : 0u) |
           (copyV ? RF_COPY_VERTICAL : 0u) | (copyD ? RF_COPY_DIAGONAL : 0u);
}

uvec2 _RF_UnpackTile(uint packed) { return uvec2(packed & 0xFFFFu, packed >> 16u); }

// Roughness of IN_NORMAL_ROUGHNESS.w as the rules read it: NaN counts as 1 (rough), clamped to [0, 1].
float _RF_Roughness(float w) { return clamp(_NRD_Sanitize(w, 1.0), 0.0, 1.0); }

// Per-pixel rules of document 002 ("per pixel decision"): a mirror is traced and not denoised; a
// pixel within the roughness threshold needs the denoiser.
bool _RF_IsMirror(bool isValid, float roughness, float mirrorRoughness, float roughnessThreshold)
{
    return isValid && roughness < mirrorRoughness && roughness <= roughnessThreshold;
}

bool _RF_NeedsDenoiser(bool isValid, float roughness, float mirrorRoughness, float roughnessThreshold)
{
    return isValid && !(roughness < mirrorRoughness) && roughness <= roughnessThreshold;
}

// Do two pixels of a quad that need the denoiser lie on one surface (a ray of one may be copied to
// the other)? Normals within about 25 degrees, roughness as the reprojection's history test, viewZ
// within 20%.
bool _RF_IsSameSurface(vec3 Na, float roughnessA, float viewZA, vec3 Nb, float roughnessB, float viewZB)
{
    return dot(Na, Nb) > 0.9 && abs(roughnessA - roughnessB) < 0.05 + 0.1 * min(roughnessA, roughnessB) &&
           abs(viewZA - viewZB) < 0.2 * min(viewZA, viewZB);
}

// Is quad position 'q' (x & 1 | (y & 1) << 1) a base ray of this frame at 'raysPerQuad' rays per quad?
// 1: one position, rotating through the quad over 4 frames; 2: one diagonal, alternating; 4: all.
bool _RF_IsBaseRay(uint q, uint frameIndex, uint raysPerQuad)
{
    if (raysPerQuad >= 4u)
        return true;
    if (raysPerQuad == 2u)
        return ((q == 0u || q == 3u) ? 0u : 1u) == (frameIndex & 1u);
    const uint order[4] = uint[4](0u, 3u, 1u, 2u);
    return q == order[frameIndex & 3u];
}

#endif

#ifdef REFLECTION_DENOISE_PASS
// Pixel of this invocation in the tile the indirect dispatch assigned to its group.
uvec2 _RF_TilePixel(uint packedTile) { return _RF_UnpackTile(packedTile) * 8u + gl_LocalInvocationID.xy; }

struct RfSurface
{
    bool isInside;
    bool needsDenoiser;
    bool isMirror;
    float viewZ;
    vec3 N;
    float roughness;
};

RfSurface _RF_LoadSurface(texture2D viewZTexture, texture2D normalRoughnessTexture, ivec2 p)
{
    RfSurface s;
    s.isInside = all(greaterThanEqual(p, ivec2(0))) && all(lessThan(uvec2(p), gResourceSize));
    s.viewZ = 0.0;
    vec4 nr = vec4(0.5, 0.5, 1.0, 1.0);
    if (s.isInside)
    {
        s.viewZ = texelFetch(sampler2D(viewZTexture, gNearestClamp), p, 0).x;
        nr = texelFetch(sampler2D(normalRoughnessTexture, gNearestClamp), p, 0);
    }
    bool isValid = s.isInside && !_NRD_IsSky(s.viewZ);
    s.roughness = _RF_Roughness(nr.w);
    s.N = NRD_FrontEnd_UnpackNormalAndRoughness(nr).xyz;
    s.needsDenoiser = _RF_NeedsDenoiser(isValid, s.roughness, gMirrorRoughness, gRoughnessThreshold);
    s.isMirror = _RF_IsMirror(isValid, s.roughness, gMirrorRoughness, gRoughnessThreshold);
    return s;
}

// Edge-stopping weight of neighbour 's' for centre 'c' at world positions 'Xs' / 'Xc': normal power,
// Gaussian of the relative plane distance (percent of viewZ, sigma gDepthSigma), roughness.
float _RF_EdgeWeight(RfSurface c, vec3 Xc, RfSurface s, vec3 Xs, float normalPower)
{
    if (!s.needsDenoiser)
        return 0.0;
    float wN = pow(max(dot(c.N, s.N), 0.0), normalPower);
    float d = abs(dot(c.N, Xs - Xc)) / max(abs(c.viewZ), NRD_EPS) * 100.0;
    float wZ = exp(-0.5 * d * d / (gDepthSigma * gDepthSigma));
    float wR = exp(-abs(s.roughness - c.roughness) * 20.0);
    return wN * wZ * wR;
}

// Standard deviation in world units of the spatial kernels around the surface point: twice the
// footprint of the reflection lobe at the hit distance (the tangent of the half-angle that holds most
// of the GGX energy is about 0.75 a, a = roughness^2), at least half a pixel. A close hit reflects
// sharply; at grazing angles the pixels stretch along the surface, so the kernel narrows on screen
// in that direction by itself.
float _RF_FootprintSigma(float normHitDist, float viewZ, float roughness, vec4 hitDistParams)
{
    float hitDist = _NRD_GetHitDist(normHitDist, viewZ, hitDistParams, roughness);
    float pixelSize = abs(viewZ) / gProjectY;
    return max(hitDist * 1.5 * roughness * roughness, 0.5 * pixelSize);
}

vec4 _RF_LoadRadiance(texture2D t, ivec2 p)
{
    vec4 v = _NRD_Sanitize(texelFetch(sampler2D(t, gNearestClamp), p, 0), 0.0);
    return vec4(clamp(v.xyz, vec3(0.0), vec3(NRD_FP16_MAX)), clamp(v.w, 0.0, 1.0));
}
#endif
