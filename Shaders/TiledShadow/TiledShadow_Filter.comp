#version 450
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_control_flow_attributes : require

// TILED_SHADOW edge-avoiding a-trous pass (document 000, "Denoiser shadows filter"): 3x3 taps
// TILED_SHADOW_STEP pixels apart with kernel weights 1 (centre) and 2/3 per axis, multiplied by
//   exp(-|shadow - shadow'| / sigma)          sigma from the 3x3-filtered variance (at most twice
//                                             the pixel's own sigma), smaller toward a dark centre,
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
// The shadow term's sigma shrinks toward a dark centre: sigma * (s + b) / (1 + b), s the centre's
// value. A dark centre takes little from brighter neighbours (next to a value near 0 a small
// difference is a large relative error: a lit penumbra bleeding into umbra); a bright centre
// still takes from darker ones (a lit sample in a dark penumbra).
#define TS_DARK_BIAS 1.0
#define LOG2_E 1.44269504
#define LOG2_TWO_THIRDS -0.5849625

// Sky and pixels outside the image hold zeros: viewZ 0 marks them, their zero normal gives them
// zero weight.
shared uint sShadow[REGION * REGION];   // packHalf2x16(shadow, variance).
shared vec4 sGeometry[REGION * REGION]; // View-space normal (the plane test needs it there), viewZ: one load per tap.
shared uint sTileClass[GROUP_TILES_X * GROUP_TILES_Y];

float Pow32(float x)
{
    x *= x;
    x *= x;
    x *= x;
    x *= x;
    return x * x;
}

// One output texel ('center' indexes the shared arrays); 'isPower32' selects the fast normal weight.
vec2 FilterTexel(int center, ivec2 pixel, bool isPower32)
{
    vec2 shadowCenter = unpackHalf2x16(sShadow[center]);
    vec4 geometryCenter = sGeometry[center];
    float zCenter = geometryCenter.w;

    // Variance prefiltered with a 3x3 Gaussian (1/4, 1/8, 1/16), at most 4x the pixel's own: a
    // settled umbra or lit pixel (variance 0) next to a penumbra takes nothing from it.
    float variance = 0.0;
    for (int dy = -1; dy <= 1; dy++)
        for (int dx = -1; dx <= 1; dx++)
            variance += (dx == 0 ? 0.5 : 0.25) * (dy == 0 ? 0.5 : 0.25) * unpackHalf2x16(sShadow[center + dy * REGION + dx]).y;
    variance = min(variance, 4.0 * shadowCenter.y);
    float shadowScale = LOG2_E * inversesqrt(max(variance, 0.0) + 1e-9);

    // Tangent plane of the centre in view space: plane(X') = dot(Nv, X') - dot(Nv, Xc) with
    // X' = z' * (ndc'.x * f.x + f.y, ndc'.y * f.z + f.w, sign); per tap it costs two FMAs.
    vec3 N = geometryCenter.xyz;
    vec2 ndc = _NRD_PixelUv(pixel) * 2.0 - 1.0;
    float planeCenter = N.x * (ndc.x * gFrustum.x + gFrustum.y) + N.y * (ndc.y * gFrustum.z + gFrustum.w) + N.z * gViewZSign;
    vec2 planeStep = N.xy * gFrustum.xz * 2.0 * gInvResourceSize * float(TILED_SHADOW_STEP);
    float planeScale = gPlaneDistanceScale / max(zCenter, 1e-30); // Denormal viewZ: no Inf * 0.
    float planeOffset = zCenter * planeCenter;

    // The shadow is averaged as the centre plus the weighted mean of the taps' differences from it:
    // where every tap equals the centre (a lit or shadowed area) the result is the centre exactly.
    // The weighted mean itself came out a few ulps off (fp32 division is not exact on every device),
    // and storing fp16 rounded toward zero turned a lit 1 into 0.9995: FLIP, which weighs such
    // differences across a whole lit area, read 2-4% more at 64x64 on the NVIDIA H200 than on lavapipe.
    float weightSum = 1.0;
    vec2 sum = vec2(0.0, shadowCenter.y); // Weighted differences from the centre; weighted variance.
    for (int dy = -1; dy <= 1; dy++)
    {
        for (int dx = -1; dx <= 1; dx++)
        {
            if (dx == 0 && dy == 0)
                continue;
            int i = center + (dy * REGION + dx) * TILED_SHADOW_STEP;
            vec4 geometry = sGeometry[i];
            float z = geometry.w;
            vec2 shadow = unpackHalf2x16(sShadow[i]);
            float NoN = max(N.x * geometry.x + N.y * geometry.y + N.z * geometry.z, 0.0);
            float plane = z * (planeCenter + float(dx) * planeStep.x + float(dy) * planeStep.y) - planeOffset;
            float kernel = (dx != 0 ? LOG2_TWO_THIRDS : 0.0) + (dy != 0 ? LOG2_TWO_THIRDS : 0.0);
            // A dark centre takes less: relative to a small value a difference is a large error.
            float darkness = (1.0 + TS_DARK_BIAS) / (shadowCenter.x + TS_DARK_BIAS);
            float exponent = kernel - abs(shadow.x - shadowCenter.x) * shadowScale * darkness - abs(plane) * planeScale;
            float w;
            if (isPower32)
                w = exp2(exponent) * Pow32(NoN); // Zero for sky and outside (zero normal).
            else
                w = z == 0.0 ? 0.0 : exp2(exponent + gNormalPower * log2(max(NoN, 1e-8)));
            sum += vec2(w * (shadow.x - shadowCenter.x), w * w * shadow.y);
            weightSum += w;
        }
    }
    return vec2(clamp(shadowCenter.x + sum.x / weightSum, 0.0, 1.0), sum.y / (weightSum * weightSum));
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
    uint moments = 0u;
    if (gIsFirstPass != 0u && isInside)
        moments = texelFetch(usampler2D(gIn_Moments, gNearestClamp), pixel, 0).x;
    barrier();

    bool isGroupSkipped = true;
    for (uint i = 0u; i < GROUP_TILES_X * GROUP_TILES_Y; i++)
        isGroupSkipped = isGroupSkipped && sTileClass[i] != TS_TILE_FILTERED;
    uint tileClass = sTileClass[uint(local.y / TS_TILE_H) * GROUP_TILES_X + uint(local.x / TS_TILE_W)];

    float result = tileClass == TS_TILE_LIT ? 1.0 : 0.0;
    float resultVariance = 0.0;
    // The next frame's history is the classification's temporal result, unfiltered: spatially
    // filtered history would carry this frame's blur (early, boosted frames) for many frames.
    float temporal = result;

    if (!isGroupSkipped)
    {
        // Samples of the group and its border.
        ivec2 regionOrigin = groupOrigin - BORDER;
        mat3 viewToWorld = mat3(gViewToWorld);
        // Kept as a loop: unrolled, the loads of every iteration would be in flight at once, which
        // costs registers (occupancy) for the larger regions.
        [[dont_unroll]] for (uint i = threadIndex; i < REGION * REGION; i += GROUP_SIZE * GROUP_SIZE)
        {
            ivec2 p = regionOrigin + ivec2(i % REGION, i / REGION);
            float z = 0.0;
            vec2 shadow = vec2(0.0);
            vec3 N = vec3(0.0);
            if (all(lessThan(uvec2(p), gResourceSize)))
            {
                z = texelFetch(sampler2D(gIn_ViewZ, gNearestClamp), p, 0).x;
                shadow = _TS_FilterInput(texelFetch(sampler2D(gIn_Shadow, gNearestClamp), p, 0).xy);
                N = NRD_FrontEnd_UnpackNormalAndRoughness(texelFetch(sampler2D(gIn_Normal, gNearestClamp), p, 0)).xyz;
                N = N * viewToWorld; // Transposed rotation: world -> view.
                if (_NRD_IsSky(z))
                {
                    z = 0.0;
                    shadow = vec2(0.0);
                    N = vec3(0.0);
                }
            }
            sShadow[i] = packHalf2x16(shadow);
            sGeometry[i] = vec4(N, z);
        }
        barrier();

        if (tileClass == TS_TILE_FILTERED && !isSkyPixel)
        {
            int center = (local.y + BORDER) * REGION + local.x + BORDER;
            vec2 own = texelFetch(sampler2D(gIn_Shadow, gNearestClamp), pixel, 0).xy; // Undecoded (TS_OUTPUT_SAMPLE).
            if (gIsFirstPass != 0u)
                temporal = own.x;
            vec2 filtered = gNormalPower == 32.0 ? FilterTexel(center, pixel, true) : FilterTexel(center, pixel, false);
            result = filtered.x;
            resultVariance = filtered.y;
            // A lit sample output as it is (TS_OUTPUT_SAMPLE) stays so in every pass: lit taps hand it
            // their variance in this one, with which the next would darken it from a shadow beside it
            // (lit pixels at 0.98-0.999 next to moving edges). A shadowed one is left to the passes
            // (kept dark as well, the moving lamps' and occluders' scenes lost up to 7%).
            if (own.y == TS_OUTPUT_SAMPLE - 1.0)
                resultVariance = own.y;
        }
    }

    if (!isInside)
        return;

    if (gIsFirstPass != 0u && (moments & TS_MOMENTS_HELD) != 0u)
        temporal = texelFetch(sampler2D(gIn_Shadow, gNearestClamp), pixel, 0).x;

    if (gIsFirstPass != 0u)
    {
        // Sky keeps its viewZ (never matches a surface) and no samples.
        imageStore(gOut_State, pixel, uvec4(_TS_PackState(viewZ, temporal, isSkyPixel ? 0u : moments), 0u, 0u));
    }
    if (!isSkyPixel)
    {
        // Stored as the nearest fp16 value: a lit pixel that took 3e-5 of a shadowed tap read 1 - 2^-11
        // where stores round towards zero (lavapipe); FLIP weighs such a difference at about 10 times
        // its size (mesh_thin at 64x64: 77 pixel-frames, a third of its excess over the input's FLIP).
        if (gIsLastPass != 0u)
            imageStore(gOut_Final, pixel, vec4(_NRD_NearestFp16(clamp(result, 0.0, 1.0))));
        else
            imageStore(gOut_Shadow, pixel, vec4(_NRD_NearestFp16(result), resultVariance, 0.0, 0.0));
    }
}
