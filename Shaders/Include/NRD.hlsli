// Public shader helpers for applications, HLSL version of NRD.glsl: the same functions, with the
// same names, arguments and results (Tests/ShaderHelpersTests.cpp checks both on the GPU).
// Include it in the ray tracing / shading pass that writes the denoiser inputs, and in the pass
// that consumes the denoised outputs. Plain HLSL (SM 5.0+, DXC, glslang's HLSL front end); no
// resources, no vector ternaries (valid under HLSL 2021 too).
#ifndef NRD_HLSLI
#define NRD_HLSLI

// Largest finite FP16 value: "no hit" / "unknown" marker that survives RG16f storage.
#define NRD_FP16_MAX 65504.0

// Value to write into IN_SHADOWDATA for sky pixels (they are skipped anyway).
#define SIGMA_INF_SHADOW float2(1.0, NRD_FP16_MAX)

// Replaces NaN / Inf by 'replacement'.
float _NRD_Sanitize(float x, float replacement) { return (isnan(x) || isinf(x)) ? replacement : x; }
float3 _NRD_Sanitize(float3 v, float replacement)
{
    return float3(_NRD_Sanitize(v.x, replacement), _NRD_Sanitize(v.y, replacement), _NRD_Sanitize(v.z, replacement));
}

//==================================================================================================
// Normal + roughness (IN_NORMAL_ROUGHNESS): .xyz = n * 0.5 + 0.5 (world space), .w = linear roughness.
//==================================================================================================

float4 NRD_FrontEnd_PackNormalAndRoughness(float3 N, float linearRoughness)
{
    float len = length(N);
    N = (len > 1e-8 && !isnan(len) && !isinf(len)) ? N / len : float3(0.0, 0.0, 1.0);
    return float4(N * 0.5 + 0.5, clamp(_NRD_Sanitize(linearRoughness, 1.0), 0.0, 1.0));
}

float4 NRD_FrontEnd_UnpackNormalAndRoughness(float4 p)
{
    float3 N = p.xyz * 2.0 - 1.0;
    float len = length(N);
    N = (len > 1e-6 && !isnan(len) && !isinf(len)) ? N / len : float3(0.0, 0.0, 1.0);
    return float4(N, clamp(_NRD_Sanitize(p.w, 1.0), 0.0, 1.0));
}

//==================================================================================================
// Radiance + hit distance front end (REBLUR, RELAX), see NRD.glsl. hitDistParams = (A, B, C, D) =
// nrd::HitDistanceParameters; normalization f = (A + |viewZ| * B) * lerp(1, C, saturate(exp2(D * roughness^2))).
//==================================================================================================

float _NRD_GetHitDistNormalization(float viewZ, float4 hitDistParams, float roughness)
{
    float z = abs(_NRD_Sanitize(viewZ, 0.0));
    float r = clamp(_NRD_Sanitize(roughness, 1.0), 0.0, 1.0);
    return (hitDistParams.x + z * hitDistParams.y) * lerp(1.0, hitDistParams.z, clamp(exp2(hitDistParams.w * r * r), 0.0, 1.0));
}

// Normalized hit distance in [0, 1]; NaN or negative hitDist counts as 0, +Inf / NRD_FP16_MAX as a miss (1).
float REBLUR_FrontEnd_GetNormHitDist(float hitDist, float viewZ, float4 hitDistParams, float roughness)
{
    float d = isnan(hitDist) ? 0.0 : max(hitDist, 0.0);
    float f = _NRD_GetHitDistNormalization(viewZ, hitDistParams, roughness);
    return d >= NRD_FP16_MAX ? 1.0 : clamp(d / f, 0.0, 1.0);
}

// IN_DIFF_RADIANCE_HITDIST / IN_SPEC_RADIANCE_HITDIST texel; 'sanitize' clears NaN / Inf first.
float4 REBLUR_FrontEnd_PackRadianceAndNormHitDist(float3 radiance, float normHitDist, bool sanitize)
{
    if (sanitize)
    {
        radiance = _NRD_Sanitize(radiance, 0.0);
        normHitDist = _NRD_Sanitize(normHitDist, 0.0);
    }
    return float4(clamp(radiance, 0.0, NRD_FP16_MAX), clamp(normHitDist, 0.0, 1.0));
}

// OUT_DIFF_RADIANCE_HITDIST / OUT_SPEC_RADIANCE_HITDIST texel -> .rgb radiance (>= 0), .w normHitDist.
float4 REBLUR_BackEnd_UnpackRadianceAndNormHitDist(float4 data)
{
    return float4(max(_NRD_Sanitize(data.xyz, 0.0), 0.0), clamp(_NRD_Sanitize(data.w, 0.0), 0.0, 1.0));
}

// Specular hit distance of one segment of a multi-bounce path (document 004), see NRD.glsl.
float NRD_GetCorrectedHitDist(float hitDist, float bounceIndex, float roughnessAlongPath, float importance)
{
    float d = isnan(hitDist) ? 0.0 : clamp(hitDist, 0.0, NRD_FP16_MAX);
    float later = max(_NRD_Sanitize(bounceIndex, 1.0) - 1.0, 0.0); // 0 for the first bounce.
    float m = clamp(_NRD_Sanitize(roughnessAlongPath, 0.0), 0.0, 64.0); // A sum over at most 64 bounces.
    m *= m;
    float k = 1.0 - exp(-m * later);
    float weight = clamp(_NRD_Sanitize(importance, 0.0), 0.0, 1.0) / (1.0 + later * later * m);
    return weight * d / (1.0 + d * k);
}

//==================================================================================================
// SIGMA front end (see NRD.glsl for the meaning of the arguments and of the result).
//==================================================================================================

float _SIGMA_PenumbraOverViewZ(float viewZ, float distanceToOccluder, float tanOfLightAngularRadius)
{
    float d = _NRD_Sanitize(distanceToOccluder, NRD_FP16_MAX);
    float t = max(_NRD_Sanitize(tanOfLightAngularRadius, 0.0), 0.0);
    float z = max(abs(_NRD_Sanitize(viewZ, 1.0)), 1e-6);
    if (d >= NRD_FP16_MAX)
        return NRD_FP16_MAX;
    return min(max(d, 0.0) * t / z, NRD_FP16_MAX * 0.5);
}

float2 SIGMA_FrontEnd_PackShadow(float viewZ, float distanceToOccluder, float tanOfLightAngularRadius)
{
    float d = _NRD_Sanitize(distanceToOccluder, NRD_FP16_MAX);
    float visibility = d >= NRD_FP16_MAX ? 1.0 : 0.0;
    return float2(visibility, _SIGMA_PenumbraOverViewZ(viewZ, distanceToOccluder, tanOfLightAngularRadius));
}

// With translucency (SIGMA_SHADOW_TRANSLUCENCY): fills IN_SHADOW_TRANSLUCENCY.
float2 SIGMA_FrontEnd_PackShadow(float viewZ, float distanceToOccluder, float tanOfLightAngularRadius,
                                 float3 translucency, out float4 shadowTranslucency)
{
    float2 shadowData = SIGMA_FrontEnd_PackShadow(viewZ, distanceToOccluder, tanOfLightAngularRadius);
    float3 t = clamp(_NRD_Sanitize(translucency, 0.0), 0.0, 1.0);
    shadowTranslucency = float4(shadowData.x, shadowData.x > 0.5 ? float3(1.0, 1.0, 1.0) : t);
    return shadowData;
}

// Multiple lights: data[0] = sum of L * S, data[1] = (sum of weights, sum of weight * penumbra,
// sum of weight * visibility). float2x3: two rows of float3, indexed like GLSL's mat2x3 columns.
float2x3 SIGMA_FrontEnd_MultiLightStart()
{
    return float2x3(0.0, 0.0, 0.0, 0.0, 0.0, 0.0);
}

void SIGMA_FrontEnd_MultiLightUpdate(float3 L, float distanceToOccluder, float tanOfLightAngularRadius, float weight,
                                     inout float2x3 multiLightShadowData)
{
    L = max(_NRD_Sanitize(L, 0.0), 0.0);
    float d = _NRD_Sanitize(distanceToOccluder, NRD_FP16_MAX);
    float visibility = d >= NRD_FP16_MAX ? 1.0 : 0.0;
    float w = max(_NRD_Sanitize(weight, 0.0), 0.0);
    // Penumbra in world units here; divided by viewZ in MultiLightEnd.
    float penumbra = d >= NRD_FP16_MAX ? 0.0 : max(d, 0.0) * max(_NRD_Sanitize(tanOfLightAngularRadius, 0.0), 0.0);
    multiLightShadowData[0] += L * visibility;
    multiLightShadowData[1] += float3(w, w * penumbra, w * visibility);
}

float2 SIGMA_FrontEnd_MultiLightEnd(float viewZ, float2x3 multiLightShadowData, float3 Lsum, out float4 shadowTranslucency)
{
    Lsum = max(_NRD_Sanitize(Lsum, 0.0), 0.0);
    float3 ratio = clamp(multiLightShadowData[0] / max(Lsum, 1e-12), 0.0, 1.0);
    float3 translucency = float3(Lsum.x > 1e-12 ? ratio.x : 1.0, Lsum.y > 1e-12 ? ratio.y : 1.0,
                                 Lsum.z > 1e-12 ? ratio.z : 1.0);
    float wSum = multiLightShadowData[1].x;
    float visibility = wSum > 0.0 ? multiLightShadowData[1].z / wSum : 1.0;
    float penumbraWorld = wSum > 0.0 ? multiLightShadowData[1].y / wSum : 0.0;
    float z = max(abs(_NRD_Sanitize(viewZ, 1.0)), 1e-6);
    float penumbra = visibility >= 1.0 ? NRD_FP16_MAX : min(penumbraWorld / z, NRD_FP16_MAX * 0.5);
    shadowTranslucency = float4(visibility, translucency);
    return float2(visibility, penumbra);
}

//==================================================================================================
// SIGMA back end: OUT_SHADOW_TRANSLUCENCY -> .x shadow visibility in [0, 1], .yzw translucency.
// Non-finite values (which the denoiser never writes) decode as fully lit.
//==================================================================================================

float4 SIGMA_BackEnd_UnpackShadow(float4 shadowTranslucency)
{
    float4 v = shadowTranslucency;
    v = float4(_NRD_Sanitize(v.x, 1.0), _NRD_Sanitize(v.yzw, 1.0));
    return clamp(v, 0.0, 1.0);
}

#endif
