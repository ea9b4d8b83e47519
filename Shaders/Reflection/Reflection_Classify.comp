#version 450
#extension GL_GOOGLE_include_directive : require

// REFLECTION classification (document 002, "per pixel decision pipe" and "tile classification").
// Shared memory only (no subgroup operations), so any subgroup size works.

#include "Bindings.glsl"
#include "Reflection_Classify.resources.h"
#include "CommonFrame.glsl"
#include "Reflection_Common.glsl"

shared uint sNeeds[64];   // Pixel needs the denoiser.
shared uint sTraces[64];  // Pixel traces a ray.
shared uint sScan[2][64]; // Prefix sum (Hillis-Steele, double buffered).
shared uint sRayBase;
shared uint sTileNeeded;

uint LocalIndex(uvec2 local) { return local.x + local.y * 8u; }

void main()
{
    uvec2 local = gl_LocalInvocationID.xy;
    uvec2 tile = gl_WorkGroupID.xy;
    uvec2 pixel = tile * 8u + local;
    uint index = LocalIndex(local);
    bool inside = all(lessThan(pixel, gResourceSize));
    if (index == 0u)
        sTileNeeded = 0u;

    float viewZ = 0.0;
    vec4 normalRoughness = vec4(0.5, 0.5, 1.0, 1.0);
    float variance = 0.0;
    if (inside)
    {
        viewZ = texelFetch(sampler2D(gIn_ViewZ, gNearestClamp), ivec2(pixel), 0).x;
        normalRoughness = texelFetch(sampler2D(gIn_NormalRoughness, gNearestClamp), ivec2(pixel), 0);
        variance = texelFetch(sampler2D(gIn_TemporalVariance, gNearestClamp), ivec2(pixel), 0).x;
    }
    bool isValid = inside && !_NRD_IsSky(viewZ);
    float roughness = _RF_Roughness(normalRoughness.w);
    bool isMirror = _RF_IsMirror(isValid, roughness, gMirrorRoughness, gRoughnessThreshold);
    bool needsDenoiser = _RF_NeedsDenoiser(isValid, roughness, gMirrorRoughness, gRoughnessThreshold);
    uint q = (local.x & 1u) | ((local.y & 1u) << 1u);
    bool isGuided = (gFlags & REFLECTION_FLAG_GUIDED_TRACING) != 0u && (gFlags & REFLECTION_FLAG_HISTORY_VALID) != 0u;
    // NaN variance (never written by the method) counts as high: trace.
    bool isVarianceHigh = isGuided && !(variance <= gTemporalVarianceThreshold);
    bool wantsRay = isMirror || (needsDenoiser && (_RF_IsBaseRay(q, gFrameIndex, gRaysPerQuad) || isVarianceHigh));

    sNeeds[index] = needsDenoiser ? 1u : 0u;
    sTraces[index] = wantsRay ? 1u : 0u;
    barrier();

    // Quad neighbours: horizontal, vertical, diagonal.
    uint iH = LocalIndex(local ^ uvec2(1u, 0u));
    uint iV = LocalIndex(local ^ uvec2(0u, 1u));
    uint iD = LocalIndex(local ^ uvec2(1u, 1u));
    // A quad whose base rays all fell on pixels that need no ray still gets one: its first pixel
    // (in quad order) that needs the denoiser traces.
    bool quadTraces = sTraces[index] + sTraces[iH] + sTraces[iV] + sTraces[iD] != 0u;
    bool isFirstNeeding = true;
    for (uint k = 0u; k < q; k++)
    {
        uvec2 o = (local & ~uvec2(1u)) + uvec2(k & 1u, k >> 1u);
        isFirstNeeding = isFirstNeeding && sNeeds[LocalIndex(o)] == 0u;
    }
    bool traces = wantsRay || (!quadTraces && needsDenoiser && isFirstNeeding);
    barrier();
    sTraces[index] = traces ? 1u : 0u;
    barrier();

    // Copies: a pixel that needs the denoiser and traces nothing takes the ray of its horizontal
    // neighbour, else its vertical one, else the diagonal one.
    bool tH = sTraces[iH] != 0u, tV = sTraces[iV] != 0u, tD = sTraces[iD] != 0u;
    bool copyH = traces && sNeeds[iH] != 0u && !tH;
    bool copyV = traces && sNeeds[iV] != 0u && !tV && !tD;
    bool copyD = traces && sNeeds[iD] != 0u && !tD && !tV && !tH;

    // Local prefix sum of the rays, then one atomic per group.
    sScan[0][index] = traces ? 1u : 0u;
    barrier();
    uint src = 0u;
    for (uint offset = 1u; offset < 64u; offset <<= 1u)
    {
        uint v = sScan[src][index];
        if (index >= offset)
            v += sScan[src][index - offset];
        sScan[1u - src][index] = v;
        src = 1u - src;
        barrier();
    }
    uint inclusive = sScan[src][index];
    if (index == 63u)
        sRayBase = inclusive == 0u ? 0u : atomicAdd(gCounters[RF_WORD_LIVE_RAYS], inclusive);
    if (needsDenoiser || isMirror)
        atomicOr(sTileNeeded, 1u);
    barrier();
    if (traces)
        gRayList[sRayBase + inclusive - 1u] = _RF_PackRay(pixel, copyH, copyV, copyD);

    if (index == 0u && sTileNeeded != 0u)
    {
        uint slot = atomicAdd(gCounters[RF_WORD_LIVE_TILES], 1u);
        gTileList[slot] = tile.x | (tile.y << 16u);
    }

    // History of the surface for the next frame's disocclusion test. Pixels the denoiser does not
    // process get an impossible roughness, so that history is never taken from them.
    if (inside)
    {
        imageStore(gOut_ViewZHistory, ivec2(pixel), vec4(isValid ? viewZ : 0.0));
        vec4 n = NRD_FrontEnd_UnpackNormalAndRoughness(normalRoughness);
        imageStore(gOut_NormalRoughnessHistory, ivec2(pixel), vec4(n.xyz, needsDenoiser ? roughness : -1.0));
    }
}
