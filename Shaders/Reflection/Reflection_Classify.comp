#version 450
#extension GL_GOOGLE_include_directive : require

// REFLECTION classification (document 002, "per pixel decision pipe" and "tile classification").
// Shared memory only (no subgroup operations), so any subgroup size works.

#include "Bindings.glsl"
#include "Reflection_Classify.resources.h"
#include "CommonFrame.glsl"
#include "Reflection_Common.glsl"

shared uint sNeeds[64];   // Pixel needs the denoiser.
shared uint sTraces[64];  // Pixel wants a ray (base or variance-guided).
shared vec4 sSurface[64]; // Normal, roughness.
shared float sViewZ[64];
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
    sSurface[index] = vec4(NRD_FrontEnd_UnpackNormalAndRoughness(normalRoughness).xyz, roughness);
    sViewZ[index] = viewZ;
    barrier();

    // Quad members in quad order (0: even x, even y; 1: odd x; 2: odd y; 3: both odd), and which of
    // them share this surface: a ray is only ever copied within a surface (a thin object in front
    // of a floor must not receive the floor's reflection).
    uvec2 quadBase = local & ~uvec2(1u);
    uint members[4];
    bool wants[4], needs[4];
    for (uint k = 0u; k < 4u; k++)
    {
        members[k] = LocalIndex(quadBase + uvec2(k & 1u, k >> 1u));
        wants[k] = sTraces[members[k]] != 0u;
        needs[k] = sNeeds[members[k]] != 0u;
    }
    bool same[16];
    for (uint a = 0u; a < 4u; a++)
        for (uint b = 0u; b < 4u; b++)
        {
            vec4 sa = sSurface[members[a]], sb = sSurface[members[b]];
            same[a * 4u + b] = a == b || (needs[a] && needs[b] &&
                                          _RF_IsSameSurface(sa.xyz, sa.w, sViewZ[members[a]], sb.xyz, sb.w, sViewZ[members[b]]));
        }
    // A pixel that needs the denoiser and has no ray of its surface in the quad (no base or
    // variance-guided ray of a same-surface member, and no member before it in quad order that
    // traces for this reason) traces its own.
    bool tracesK[4];
    for (uint k = 0u; k < 4u; k++)
    {
        bool hasRay = false;
        for (uint j = 0u; j < 4u; j++)
            hasRay = hasRay || (j != k && same[k * 4u + j] && (wants[j] || (j < k && tracesK[j])));
        tracesK[k] = wants[k] || (needs[k] && !hasRay);
    }

    // Copies: a pixel that needs the denoiser and traces nothing takes the ray of its horizontal
    // neighbour, else its vertical one, else the diagonal one, each only on the same surface.
    // Member index of this pixel and of its neighbours: horizontal q ^ 1, vertical q ^ 2, diagonal q ^ 3.
    bool traces = tracesK[q];
    // Does member n take its copy from member 'from'? n's own order: n ^ 1, then n ^ 2, then n ^ 3.
    bool copyH = false, copyV = false, copyD = false;
    if (traces)
    {
        for (uint d = 1u; d < 4u; d++)
        {
            uint n = q ^ d;
            bool takes = needs[n] && !tracesK[n] && same[n * 4u + q];
            for (uint e = 1u; e < d; e++)
                takes = takes && !(tracesK[n ^ e] && same[n * 4u + (n ^ e)]);
            copyH = copyH || (d == 1u && takes);
            copyV = copyV || (d == 2u && takes);
            copyD = copyD || (d == 3u && takes);
        }
    }

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
