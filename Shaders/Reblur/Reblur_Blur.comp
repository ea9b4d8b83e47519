// REBLUR spatial passes (document 004, REBLUR: "pre-pass", "blur", "post-blur"): one pipeline, the
// pass chosen by gPassIndex.
//
// A rotated 12-tap Vogel disk on the tangent plane of the centre (its pixel footprint follows the
// surface's foreshortening), radius from _Reblur_BlurRadius (history length, hit distance,
// roughness) times gPassRadiusScale; weights from plane distance, lobe-aware normals, roughness,
// hit distance (specular) and a Gaussian falloff; radiance filtered through the roughness-based
// colour compression. The pre-pass ignores history (the length it reads is last frame's) and takes
// only pixels traced this frame (checkerboard); the post-blur rotates the kernel independently.
#version 450
#extension GL_GOOGLE_include_directive : require

#include "Bindings.glsl"
#include "Reblur_Blur.resources.h"
#include "CommonFrame.glsl"
#include "Reblur_Common.glsl"

#define TAPS 12

vec4 LoadSignal(ivec2 p)
{
    if (gPassIndex == 0u)
        return _Reblur_LoadInput(gIn_Signal, p);
    vec4 v = texelFetch(sampler2D(gIn_Signal, gNearestClamp), p, 0);
#if REBLUR_OCCLUSION
    // The post-blur reads the blur's result from the single-channel output texture.
    v = vec4(0.0, 0.0, 0.0, gPassIndex == 2u ? v.x : v.w);
#endif
    return _Reblur_Sanitize(v);
}

void Store(ivec2 pixel, vec4 v)
{
#if REBLUR_OCCLUSION
    // The blur writes the single-channel output texture (.x), the other passes RGBA textures (.w).
    v = gPassIndex == 1u ? v.wwww : vec4(0.0, 0.0, 0.0, v.w);
#endif
    imageStore(gOut_Signal, pixel, v);
}

// Diffuse: variance of a pixel's accumulated luminance, from the per-pixel deviation of its samples
// (the fast channel, Reblur_TemporalAccumulation.comp) over its history length.
float MeanVariance(ivec2 p)
{
    vec2 sigmaLength = texelFetch(sampler2D(gIn_Fast, gNearestClamp), p, 0).xy;
    float sigma = max(_NRD_Sanitize(sigmaLength.x, 0.0), 0.0);
    return sigma * sigma / max(_NRD_Sanitize(sigmaLength.y, 0.0), 1.0);
}

// Diffuse: weight of a neighbour whose accumulated luminance differs from the centre's by more than
// both means' noise allows (REBLUR_LUMA_WEIGHT_SIGMA standard deviations): shadows and stripes
// narrower than the kernel (venetian_blinds, mesh_thin) are not noise, and the geometry weights
// cannot see them.
float LumaWeight(float lumaC, float varianceC, float lumaQ, float varianceQ)
{
#if REBLUR_SPECULAR || REBLUR_OCCLUSION
    return 1.0;
#else
    float d = lumaQ - lumaC;
    float tolerance = REBLUR_LUMA_WEIGHT_SIGMA * REBLUR_LUMA_WEIGHT_SIGMA * (varianceC + varianceQ) +
                      1e-4 * lumaC * lumaC + 1e-8;
    return exp(-0.5 * d * d / tolerance);
#endif
}

// The luminance-weighted result (sum, weightSum) where the centre has neighbours of its luminance,
// the geometry-only one (sumG, weightSumG) where it has (almost) none: a pixel unlike all of its
// neighbours is more likely a rare bright or dark sample than a feature, and a luminance weight
// alone would keep it (scattered single pixels on roughness_sweep and sky). 'centerWeight' is the
// centre's part of both sums.
vec4 IsolationBlend(vec4 sum, float weightSum, vec4 sumG, float weightSumG, float centerWeight, float k)
{
    vec4 resultG = weightSumG > 0.0 ? _Reblur_Decompress(sumG / weightSumG, k) : vec4(0.0);
#if REBLUR_SPECULAR || REBLUR_OCCLUSION
    return resultG;
#else
    vec4 result = weightSum > 0.0 ? _Reblur_Decompress(sum / weightSum, k) : resultG;
    float share = (weightSum - centerWeight) / max(weightSumG - centerWeight, 1e-6);
    return weightSumG - centerWeight > 1e-6 ? mix(resultG, result, smoothstep(REBLUR_LUMA_ISOLATED_LOW, REBLUR_LUMA_ISOLATED_HIGH, share)) : result;
#endif
}

// History fix (document 004, REBLUR: "history fix"), run by the blur where the history is shorter
// than gHistoryFixFrameNum frames (disocclusion, anti-lag, confidence): a 5x5 sparse grid whose stride
// shrinks as the history grows (the history a confidence input took, the debt, counts as grown;
// specular runs it for the debt's frames longer), weighted by geometry.
vec4 HistoryFix(ivec2 pixel, ReblurSurface s, vec4 center, float historyLength)
{
    ivec2 maxPixel = ivec2(gResourceSize) - 1;
    float stride = max(gHistoryFixStride * (1.0 - historyLength / gHistoryFixFrameNum), 1.0);
    float k = _Reblur_CompressionK(s.roughness);
    vec4 sum = _Reblur_Compress(center, k);
    float weightSum = 1.0;
    vec4 sumG = sum;
    float weightSumG = 1.0;
#if !REBLUR_SPECULAR && !REBLUR_OCCLUSION
    float lumaC = _Reblur_Luma(center), varianceC = MeanVariance(pixel);
#endif
    for (int j = -2; j <= 2; j++)
    {
        for (int i = -2; i <= 2; i++)
        {
            if (i == 0 && j == 0)
                continue;
            ivec2 q = pixel + ivec2(round(vec2(i, j) * stride));
            if (any(lessThan(q, ivec2(0))) || any(greaterThan(q, maxPixel)))
                continue;
            float z = texelFetch(sampler2D(gIn_ViewZ, gNearestClamp), q, 0).x;
            if (_NRD_IsSky(z))
                continue;
            vec4 nr = NRD_FrontEnd_UnpackNormalAndRoughness(texelFetch(sampler2D(gIn_NormalRoughness, gNearestClamp), q, 0));
            vec3 Xs = _NRD_ViewPosition(_NRD_PixelUv(q), z);
            vec3 Ns = normalize(transpose(mat3(gViewToWorld)) * nr.xyz);
            vec4 v = LoadSignal(q);
            // Gaussian falloff over the grid: a flat average of the whole 5x5 grid (12x12 pixels at
            // length 0) carried light into contact shadows and corners.
            float w = _Reblur_GeometryWeight(s, Xs, Ns, nr.w) * exp(-0.25 * float(i * i + j * j));
            if (w > 0.0)
            {
#if REBLUR_SPECULAR || REBLUR_OCCLUSION
                float wl = 1.0;
#else
                float wl = LumaWeight(lumaC, varianceC, _Reblur_Luma(v), MeanVariance(q));
#endif
                sumG += _Reblur_Compress(v, k) * w;
                weightSumG += w;
                sum += _Reblur_Compress(v, k) * (w * wl);
                weightSum += w * wl;
            }
        }
    }
    return IsolationBlend(sum, weightSum, sumG, weightSumG, 1.0, k);
}

void main()
{
    ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(uvec2(pixel), gResourceSize)) || _Reblur_IsSkyTile(gIn_Tiles, pixel))
        return;
    float viewZ = texelFetch(sampler2D(gIn_ViewZ, gNearestClamp), pixel, 0).x;
    if (_NRD_IsSky(viewZ))
        return;

    bool isPrePass = gPassIndex == 0u;
    bool isTraced = !isPrePass || _Reblur_IsTraced(pixel);
    vec4 center = LoadSignal(pixel);
    ReblurSurface s = _Reblur_Surface(gIn_NormalRoughness, pixel, viewZ);
    float historyLength = isPrePass ? 0.0 : texelFetch(sampler2D(gIn_Fast, gNearestClamp), pixel, 0).y;
    historyLength = clamp(_NRD_Sanitize(historyLength, 0.0), 0.0, NRD_HISTORY_LENGTH_MAX);
    float debt = isPrePass ? 0.0 : texelFetch(sampler2D(gIn_Debt, gNearestClamp), pixel, 0).x;
    bool isLightingMoving = false;
#if !REBLUR_SPECULAR && !REBLUR_OCCLUSION
    // Diffuse radiance: the debt texel holds the lighting change record (Reblur_Common.glsl).
    isLightingMoving = _NRD_LightingChange_IsMoving(_NRD_LightingChange_UnpackRecord(debt));
    debt = 0.0;
#endif
    float fixLength = historyLength + clamp(_NRD_Sanitize(debt, 0.0), 0.0, 1.0) * REBLUR_DEBT_SCALE;
    float radius = _Reblur_BlurRadius(historyLength, center.w, viewZ, s.roughness) * gPassRadiusScale;
    if (isLightingMoving)
        radius *= REBLUR_MOVING_RADIUS_SCALE;
    bool isReference = (gFlags & REBLUR_FLAG_REFERENCE) != 0u;
#if REBLUR_SPECULAR
    // Specular: a history the confidence cut keeps the fix for the debt's frames longer. The cut
    // restarts specular histories (Reblur_TemporalAccumulation.comp), every neighbour's on the
    // surface whose lighting changed with them, and on a glossy surface the blur's radius is scaled
    // by 2 roughness (_Reblur_BlurRadius): the dense 5x5 fix averages more of the regrowing
    // histories' noise for those frames, REBLUR_SPECULAR_DEBT_FIX_SCALE times the debt's (fast_occluder
    // 128x128, the box's shadow crossing a glossy sphere: relMSE with / without confidence 1.008x ->
    // 0.979x on the NVIDIA H100 with the debt's frames once; Shaders/Confidence/README.md).
    float fixFrames = gHistoryFixFrameNum + REBLUR_SPECULAR_DEBT_FIX_SCALE * (fixLength - historyLength);
#else
    float fixFrames = gHistoryFixFrameNum;
#endif
    if (gPassIndex == 1u && historyLength < fixFrames && !isReference && !isLightingMoving)
    {
        Store(pixel, _NRD_ClampToHalf(HistoryFix(pixel, s, center, fixLength)));
        return;
    }
    if ((isReference || radius < 0.5) && isTraced)
    {
        Store(pixel, center);
        return;
    }
    radius = max(radius, 1.0);

    // Tangent basis scaled so that one unit is 'radius' pixels at the centre.
    float worldPerPixel = viewZ / gProjectY;
    vec3 up = abs(s.Nv.z) < 0.999 ? vec3(0.0, 0.0, 1.0) : vec3(1.0, 0.0, 0.0);
    vec3 T = normalize(cross(up, s.Nv));
    vec3 B = cross(s.Nv, T);
    float angle = _Reblur_KernelAngle(pixel, gPassIndex);
    float ca = cos(angle), sa = sin(angle);
    vec3 T1 = (T * ca + B * sa) * (radius * worldPerPixel);
    vec3 B1 = (B * ca - T * sa) * (radius * worldPerPixel);

    float k = _Reblur_CompressionK(s.roughness);
    float centerWeight = isTraced ? 1.0 : 0.0;
    vec4 sum = _Reblur_Compress(center, k) * centerWeight;
    float weightSum = centerWeight;
    vec4 sumG = sum;
    float weightSumG = weightSum;
    float hitDistScale = 1.0 / max(center.w, 0.05);
#if !REBLUR_SPECULAR && !REBLUR_OCCLUSION
    bool isLumaWeighted = !isPrePass;
    float lumaC = _Reblur_Luma(center), varianceC = isLumaWeighted ? MeanVariance(pixel) : 0.0;
#endif
    for (int t = 0; t < TAPS; t++)
    {
        float r = sqrt((float(t) + 0.5) / float(TAPS));
        float phi = float(t) * 2.39996323;
        vec2 o = r * vec2(cos(phi), sin(phi));
        vec3 Xt = s.Xv + T1 * o.x + B1 * o.y;
        vec4 clip = gViewToClip * vec4(Xt, 1.0);
        if (!(clip.w > NRD_EPS))
            continue;
        ivec2 q = ivec2(floor(((clip.xy / clip.w) * 0.5 + 0.5) * vec2(gResourceSize)));
        if (any(lessThan(q, ivec2(0))) || any(greaterThanEqual(uvec2(q), gResourceSize)))
            continue;
        if (isPrePass && !_Reblur_IsTraced(q))
            continue;
        float z = texelFetch(sampler2D(gIn_ViewZ, gNearestClamp), q, 0).x;
        if (_NRD_IsSky(z))
            continue;
        vec4 nr = NRD_FrontEnd_UnpackNormalAndRoughness(texelFetch(sampler2D(gIn_NormalRoughness, gNearestClamp), q, 0));
        vec3 Xs = _NRD_ViewPosition(_NRD_PixelUv(q), z);
        vec3 Ns = normalize(transpose(mat3(gViewToWorld)) * nr.xyz);
        vec4 v = LoadSignal(q);
        float w = _Reblur_GeometryWeight(s, Xs, Ns, nr.w) * exp(-2.0 * r * r);
#if REBLUR_SPECULAR
        // Reflections of different hit distances are different images.
        w *= clamp(1.0 - abs(v.w - center.w) * hitDistScale * 0.5, 0.0, 1.0);
#elif !REBLUR_OCCLUSION
        // Diffuse: a neighbour whose occluders are at another distance is lit differently (contact
        // shadows, corners); the accumulated hit distance is smooth enough to compare.
        w *= clamp(1.0 - abs(v.w - center.w) * hitDistScale, 0.0, 1.0);
        sumG += _Reblur_Compress(v, k) * w;
        weightSumG += w;
        if (isLumaWeighted && w > 0.0)
            w *= LumaWeight(lumaC, varianceC, _Reblur_Luma(v), MeanVariance(q));
#endif
        sum += _Reblur_Compress(v, k) * w;
        weightSum += w;
    }
#if REBLUR_SPECULAR || REBLUR_OCCLUSION
    vec4 result = weightSum > 0.0 ? _Reblur_Decompress(sum / weightSum, k) : center;
#else
    vec4 result = weightSumG > 0.0 ? IsolationBlend(sum, weightSum, sumG, weightSumG, centerWeight, k) : center;
#endif
    Store(pixel, _NRD_ClampToHalf(result));
}
