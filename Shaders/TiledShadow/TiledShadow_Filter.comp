#version 450
#extension GL_GOOGLE_include_directive : require

// TILED_SHADOW edge-avoiding a-trous pass (document 000, "Denoiser shadows filter"): 3x3 taps
// TILED_SHADOW_STEP pixels apart with kernel weights 1 (centre) and 2/3 per axis, multiplied by
//   exp(-|shadow - shadow'| / sigma)          sigma from the 3x3-filtered variance,
//   exp(-|plane distance| / (s * viewZ))      distance of the tap to the centre's tangent plane,
//   max(0, N.N')^normalPower.
// The variance is filtered with the squared weights, so it shrinks pass after pass. Skipped tiles
// copy their uniform value; a group whose tiles are all skipped loads nothing.
// Group: 16x16 pixels = 2x4 tiles; the samples (with a TILED_SHADOW_STEP border) live in shared memory.

#include "Bindings.glsl"
#include "TiledShadow_Filter.resources.h"
#include "CommonFrame.glsl"
#include "TiledShadow_Common.glsl"

#define GROUP_SIZE 16
#define GROUP_TILES_X 2
#define GROUP_TILES_Y 4
#define BORDER TILED_SHADOW_STEP
#define REGION (GROUP_SIZE + 2 * BORDER)
#define LOG2_E 1.44269504
#define LOG2_TWO_THIRDS -0.5849625

shared uint sShadow[REGION * REGION]; // packHalf2x16(shadow, variance).
shared float sViewZ[REGION * REGION]; // 0 for sky and outside the image.
shared float sNormalX[REGION * REGION];
shared float sNormalY[REGION * REGION];
shared float sNormalZ[REGION * REGION];
shared uint sTileClass[GROUP_TILES_X * GROUP_TILES_Y];

void WriteResult(ivec2 pixel, float shadow, float variance)
{
    if (gIsLastPass != 0u)
        imageStore(gOut_Final, pixel, vec4(clamp(shadow, 0.0, 1.0)));
    else
        imageStore(gOut_Shadow, pixel, vec4(shadow, variance, 0.0, 0.0));
}

void main()
{
    uint threadIndex = gl_LocalInvocationIndex;
    ivec2 local = ivec2(gl_LocalInvocationID.xy);
    ivec2 groupOrigin = ivec2(gl_WorkGroupID.xy) * GROUP_SIZE;
    ivec2 groupTile = ivec2(gl_WorkGroupID.xy) * ivec2(GROUP_TILES_X, GROUP_TILES_Y);
    ivec2 pixel = groupOrigin + local;
    bool isInside = all(lessThan(pixel, ivec2(gResourceSize)));

    if (threadIndex < GROUP_TILES_X * GROUP_TILES_Y)
    {
        ivec2 tile = groupTile + ivec2(threadIndex % GROUP_TILES_X, threadIndex / GROUP_TILES_X);
        sTileClass[threadIndex] = all(lessThan(uvec2(tile), _TS_TileCount(gResourceSize)))
                                    ? texelFetch(usampler2D(gIn_TileClass, gNearestClamp), tile, 0).x
                                    : TS_TILE_SKY;
    }

    // Sky pixels are never written; the first pass stores the history state of every pixel.
    float viewZ = isInside ? texelFetch(sampler2D(gIn_ViewZ, gNearestClamp), pixel, 0).x : 0.0;
    bool isSkyPixel = _NRD_IsSky(viewZ);
    vec2 moments = vec2(0.0);
    if (gIsFirstPass != 0u && isInside)
        moments = texelFetch(sampler2D(gIn_Shadow, gNearestClamp), pixel, 0).zw;
    barrier();

    bool isGroupSkipped = true;
    for (uint i = 0u; i < GROUP_TILES_X * GROUP_TILES_Y; i++)
        isGroupSkipped = isGroupSkipped && sTileClass[i] != TS_TILE_FILTERED;
    uint tileClass = sTileClass[uint(local.y / TS_TILE_H) * GROUP_TILES_X + uint(local.x / TS_TILE_W)];

    float result = tileClass == TS_TILE_LIT ? 1.0 : 0.0;
    float resultVariance = 0.0;

    if (!isGroupSkipped)
    {
        // Samples of the group and its border.
        ivec2 regionOrigin = groupOrigin - BORDER;
        for (uint i = threadIndex; i < REGION * REGION; i += GROUP_SIZE * GROUP_SIZE)
        {
            ivec2 p = regionOrigin + ivec2(i % REGION, i / REGION);
            float z = 0.0;
            vec2 shadow = vec2(0.0);
            vec3 N = vec3(0.0);
            if (all(lessThan(uvec2(p), gResourceSize)))
            {
                z = texelFetch(sampler2D(gIn_ViewZ, gNearestClamp), p, 0).x;
                if (_NRD_IsSky(z))
                    z = 0.0;
                shadow = texelFetch(sampler2D(gIn_Shadow, gNearestClamp), p, 0).xy;
                N = NRD_FrontEnd_UnpackNormalAndRoughness(texelFetch(sampler2D(gIn_Normal, gNearestClamp), p, 0)).xyz;
            }
            sShadow[i] = packHalf2x16(shadow);
            sViewZ[i] = z;
            sNormalX[i] = N.x;
            sNormalY[i] = N.y;
            sNormalZ[i] = N.z;
        }
        barrier();

        int center = (local.y + BORDER) * REGION + local.x + BORDER;
        vec2 shadowCenter = unpackHalf2x16(sShadow[center]);
        float zCenter = sViewZ[center];

        if (tileClass == TS_TILE_FILTERED && !isSkyPixel)
        {
            // Variance prefiltered with a 3x3 Gaussian (1/4, 1/8, 1/16) over the surface pixels.
            float varianceSum = 0.0, varianceWeight = 0.0;
            for (int dy = -1; dy <= 1; dy++)
            {
                for (int dx = -1; dx <= 1; dx++)
                {
                    int i = center + dy * REGION + dx;
                    if (sViewZ[i] == 0.0)
                        continue; // Sky and outside: never written, may hold anything.
                    float w = (dx == 0 ? 2.0 : 1.0) * (dy == 0 ? 2.0 : 1.0);
                    varianceSum += w * unpackHalf2x16(sShadow[i]).y;
                    varianceWeight += w;
                }
            }
            float sigma = sqrt(max(varianceSum / varianceWeight, 0.0) + 1e-9);
            float shadowScale = LOG2_E / sigma;

            // Tangent plane of the centre in view space: plane(X') = dot(Nv, X') - dot(Nv, Xc) with
            // X' = z' * (ndc'.x * f.x + f.y, ndc'.y * f.z + f.w, sign); per tap it costs one FMA.
            vec3 N = vec3(sNormalX[center], sNormalY[center], sNormalZ[center]);
            vec3 Nv = N * mat3(gViewToWorld); // Transposed rotation: world -> view.
            vec2 ndc = _NRD_PixelUv(pixel) * 2.0 - 1.0;
            float planeCenter = Nv.x * (ndc.x * gFrustum.x + gFrustum.y) + Nv.y * (ndc.y * gFrustum.z + gFrustum.w) + Nv.z * gViewZSign;
            vec2 planeStep = Nv.xy * gFrustum.xz * 2.0 * gInvResourceSize * float(TILED_SHADOW_STEP);
            float planeScale = gPlaneDistanceScale / max(zCenter, 1e-30); // Denormal viewZ: no Inf * 0.

            float weightSum = 1.0;
            vec2 sum = shadowCenter * vec2(1.0, 1.0);
            for (int dy = -1; dy <= 1; dy++)
            {
                for (int dx = -1; dx <= 1; dx++)
                {
                    if (dx == 0 && dy == 0)
                        continue;
                    int i = center + (dy * REGION + dx) * TILED_SHADOW_STEP;
                    float z = sViewZ[i];
                    if (z == 0.0)
                        continue;
                    vec2 shadow = unpackHalf2x16(sShadow[i]);
                    float NoN = max(dot(N, vec3(sNormalX[i], sNormalY[i], sNormalZ[i])), 0.0);
                    float plane = z * (planeCenter + float(dx) * planeStep.x + float(dy) * planeStep.y) - zCenter * planeCenter;
                    float kernel = (dx != 0 ? LOG2_TWO_THIRDS : 0.0) + (dy != 0 ? LOG2_TWO_THIRDS : 0.0);
                    float w = exp2(kernel - abs(shadow.x - shadowCenter.x) * shadowScale - abs(plane) * planeScale +
                                   gNormalPower * log2(max(NoN, 1e-8)));
                    sum += vec2(w, w * w) * shadow;
                    weightSum += w;
                }
            }
            result = sum.x / weightSum;
            resultVariance = sum.y / (weightSum * weightSum);
        }
    }

    if (!isInside)
        return;

    if (gIsFirstPass != 0u)
    {
        // Sky keeps its viewZ (never matches a surface) and no samples.
        float samples = isSkyPixel ? 0.0 : moments.y;
        uint history = _TS_PackHistory(isSkyPixel ? 0.0 : result, moments.x, samples);
        imageStore(gOut_State, pixel, uvec4(floatBitsToUint(viewZ), history, 0u, 0u));
    }
    if (!isSkyPixel)
        WriteResult(pixel, result, resultVariance);
}
