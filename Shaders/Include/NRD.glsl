// Public shader helpers for applications (front end: pack inputs; back end: unpack outputs).
// Include it in the ray tracing / shading pass that writes the denoiser inputs, and in the pass
// that consumes the denoised outputs. GLSL 4.50.
#ifndef NRD_GLSL
#define NRD_GLSL

// Largest finite FP16 value: "no hit" / "unknown" marker that survives RG16f storage.
#define NRD_FP16_MAX 65504.0

// Value to write into IN_SHADOWDATA for sky pixels (they are skipped anyway).
#define SIGMA_INF_SHADOW vec2(1.0, NRD_FP16_MAX)

// Replaces NaN / Inf by 'replacement'.
float _NRD_Sanitize(float x, float replacement) { return (isnan(x) || isinf(x)) ? replacement : x; }
vec3 _NRD_Sanitize(vec3 v, float replacement)
{
    return vec3(_NRD_Sanitize(v.x, replacement), _NRD_Sanitize(v.y, replacement), _NRD_Sanitize(v.z, replacement));
}

//==================================================================================================
// Normal + roughness (IN_NORMAL_ROUGHNESS): .xyz = n * 0.5 + 0.5 (world space), .w = linear roughness.
//==================================================================================================

vec4 NRD_FrontEnd_PackNormalAndRoughness(vec3 N, float linearRoughness)
{
    float len = length(N);
    N = (len > 1e-8 && !isnan(len) && !isinf(len)) ? N / len : vec3(0.0, 0.0, 1.0);
    return vec4(N * 0.5 + 0.5, clamp(_NRD_Sanitize(linearRoughness, 1.0), 0.0, 1.0));
}

vec4 NRD_FrontEnd_UnpackNormalAndRoughness(vec4 p)
{
    vec3 N = p.xyz * 2.0 - 1.0;
    float len = length(N);
    N = (len > 1e-6 && !isnan(len) && !isinf(len)) ? N / len : vec3(0.0, 0.0, 1.0);
    return vec4(N, clamp(_NRD_Sanitize(p.w, 1.0), 0.0, 1.0));
}

//==================================================================================================
// SIGMA front end.
//
// distanceToOccluder: distance from the shaded point to the first occluder along the shadow ray,
//   NRD_FP16_MAX (or any value >= it, or +Inf) if the light is visible.
// tanOfLightAngularRadius: tan of the light's angular radius as seen from the shaded point
//   (sun: a constant, e.g. tan(0.27 deg); local light: lightRadius / distanceToLight).
// viewZ: IN_VIEWZ of the pixel (positive linear depth).
//
// Result (IN_SHADOWDATA): .x = visibility in {0, 1} (or [0, 1]),
//   .y = penumbra radius at the receiver divided by viewZ (a view-distance independent angular
//   size; the denoiser turns it into pixels), NRD_FP16_MAX where the pixel is lit.
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

vec2 SIGMA_FrontEnd_PackShadow(float viewZ, float distanceToOccluder, float tanOfLightAngularRadius)
{
    float d = _NRD_Sanitize(distanceToOccluder, NRD_FP16_MAX);
    float visibility = d >= NRD_FP16_MAX ? 1.0 : 0.0;
    return vec2(visibility, _SIGMA_PenumbraOverViewZ(viewZ, distanceToOccluder, tanOfLightAngularRadius));
}

// With translucency (SIGMA_SHADOW_TRANSLUCENCY): 'translucency' is the colored transmittance of
// the occluders along the ray (1 where the light is visible). Fills IN_SHADOW_TRANSLUCENCY.
vec2 SIGMA_FrontEnd_PackShadow(float viewZ, float distanceToOccluder, float tanOfLightAngularRadius,
                               vec3 translucency, out vec4 shadowTranslucency)
{
    vec2 shadowData = SIGMA_FrontEnd_PackShadow(viewZ, distanceToOccluder, tanOfLightAngularRadius);
    vec3 t = clamp(_NRD_Sanitize(translucency, 0.0), 0.0, 1.0);
    shadowTranslucency = vec4(shadowData.x, shadowData.x > 0.5 ? vec3(1.0) : t);
    return shadowData;
}

// Multiple lights (see the quick start guide): data[0] = sum of L * S, data[1] = (sum of weights,
// sum of weight * penumbra, sum of weight * visibility).
mat2x3 SIGMA_FrontEnd_MultiLightStart()
{
    return mat2x3(vec3(0.0), vec3(0.0));
}

void SIGMA_FrontEnd_MultiLightUpdate(vec3 L, float distanceToOccluder, float tanOfLightAngularRadius, float weight,
                                     inout mat2x3 multiLightShadowData)
{
    L = max(_NRD_Sanitize(L, 0.0), vec3(0.0));
    float d = _NRD_Sanitize(distanceToOccluder, NRD_FP16_MAX);
    float visibility = d >= NRD_FP16_MAX ? 1.0 : 0.0;
    float w = max(_NRD_Sanitize(weight, 0.0), 0.0);
    // Penumbra in world units here; divided by viewZ in MultiLightEnd.
    float penumbra = d >= NRD_FP16_MAX ? 0.0 : max(d, 0.0) * max(_NRD_Sanitize(tanOfLightAngularRadius, 0.0), 0.0);
    multiLightShadowData[0] += L * visibility;
    multiLightShadowData[1] += vec3(w, w * penumbra, w * visibility);
}

vec2 SIGMA_FrontEnd_MultiLightEnd(float viewZ, mat2x3 multiLightShadowData, vec3 Lsum, out vec4 shadowTranslucency)
{
    Lsum = max(_NRD_Sanitize(Lsum, 0.0), vec3(0.0));
    vec3 translucency = multiLightShadowData[0] / max(Lsum, vec3(1e-12));
    translucency = mix(vec3(1.0), clamp(translucency, 0.0, 1.0), greaterThan(Lsum, vec3(1e-12)));
    float wSum = multiLightShadowData[1].x;
    float visibility = wSum > 0.0 ? multiLightShadowData[1].z / wSum : 1.0;
    float penumbraWorld = wSum > 0.0 ? multiLightShadowData[1].y / wSum : 0.0;
    float z = max(abs(_NRD_Sanitize(viewZ, 1.0)), 1e-6);
    float penumbra = visibility >= 1.0 ? NRD_FP16_MAX : min(penumbraWorld / z, NRD_FP16_MAX * 0.5);
    shadowTranslucency = vec4(visibility, translucency);
    return vec2(visibility, penumbra);
}

//==================================================================================================
// SIGMA back end: OUT_SHADOW_TRANSLUCENCY -> .x shadow visibility in [0, 1], .yzw translucency.
// Non-finite values (which the denoiser never writes) decode as fully lit.
//==================================================================================================

vec4 SIGMA_BackEnd_UnpackShadow(vec4 shadowTranslucency)
{
    vec4 v = shadowTranslucency;
    v = vec4(_NRD_Sanitize(v.x, 1.0), _NRD_Sanitize(v.yzw, 1.0));
    return clamp(v, 0.0, 1.0);
}

#endif
