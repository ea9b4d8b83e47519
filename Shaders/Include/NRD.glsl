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
// Radiance + hit distance front end (REBLUR, RELAX; IN_DIFF_RADIANCE_HITDIST, IN_SPEC_RADIANCE_HITDIST,
// IN_DIFF_HITDIST, IN_SPEC_HITDIST).
//
// Hit distances are stored normalized to [0, 1]: hitDist / f, saturated, with
//   f = (A + |viewZ| * B) * mix(1, C, saturate(exp2(D * roughness^2)))
// and hitDistParams = (A, B, C, D) = nrd::HitDistanceParameters (NRDSettings.h; defaults 3, 0.1, 20,
// -25, in world units). Near-mirror surfaces (roughness -> 0) get up to C times the range, since
// their reflections are sharp over longer distances. The denoiser de-normalizes with the same
// parameters, which is why they must be the ones given to the method settings. 1 means "nothing hit
// within the range" (a miss: pass NRD_FP16_MAX or +Inf). Diffuse signals pass roughness 1.
//==================================================================================================

// The normalization f above (> 0 for valid parameters). Non-finite viewZ counts as 0 and non-finite
// roughness as 1.
float _NRD_GetHitDistNormalization(float viewZ, vec4 hitDistParams, float roughness)
{
    float z = abs(_NRD_Sanitize(viewZ, 0.0));
    float r = clamp(_NRD_Sanitize(roughness, 1.0), 0.0, 1.0);
    return (hitDistParams.x + z * hitDistParams.y) * mix(1.0, hitDistParams.z, clamp(exp2(hitDistParams.w * r * r), 0.0, 1.0));
}

// Normalized hit distance in [0, 1]. hitDist: distance from the primary surface to the bounce hit (not
// including the primary hit's own distance); NaN or negative counts as 0 (an occluder at the surface),
// +Inf / NRD_FP16_MAX as a miss (1).
float REBLUR_FrontEnd_GetNormHitDist(float hitDist, float viewZ, vec4 hitDistParams, float roughness)
{
    float d = isnan(hitDist) ? 0.0 : max(hitDist, 0.0);
    float f = _NRD_GetHitDistNormalization(viewZ, hitDistParams, roughness);
    return d >= NRD_FP16_MAX ? 1.0 : clamp(d / f, 0.0, 1.0);
}

// IN_DIFF_RADIANCE_HITDIST / IN_SPEC_RADIANCE_HITDIST texel: .rgb radiance clamped to [0, NRD_FP16_MAX]
// (what RGBA16f stores), .w normHitDist clamped to [0, 1]. With 'sanitize', NaN / Inf radiance and
// hit distance channels are cleared to 0 first (without it they are the caller's responsibility).
vec4 REBLUR_FrontEnd_PackRadianceAndNormHitDist(vec3 radiance, float normHitDist, bool sanitize)
{
    if (sanitize)
    {
        radiance = _NRD_Sanitize(radiance, 0.0);
        normHitDist = _NRD_Sanitize(normHitDist, 0.0);
    }
    return vec4(clamp(radiance, vec3(0.0), vec3(NRD_FP16_MAX)), clamp(normHitDist, 0.0, 1.0));
}

// OUT_DIFF_RADIANCE_HITDIST / OUT_SPEC_RADIANCE_HITDIST texel -> .rgb denoised radiance (>= 0), .w
// denoised normalized hit distance in [0, 1] (ambient / specular occlusion). Non-finite channels, which
// the denoisers never write, decode as 0.
vec4 REBLUR_BackEnd_UnpackRadianceAndNormHitDist(vec4 data)
{
    return vec4(max(_NRD_Sanitize(data.xyz, 0.0), vec3(0.0)), clamp(_NRD_Sanitize(data.w, 0.0), 0.0, 1.0));
}

// Specular hit distance of a path with several bounces (document 004: pass a corrected hit distance,
// not the sum of the segment lengths). Sum the result over the bounces of a path, then normalize.
// The denoiser uses the hit distance for the parallax of the reflected image. The first bounce
// (bounceIndex 1) is seen directly in the mirror and counts in full. A later segment is seen through
// the surfaces the path has already reflected off: the rougher they were ('roughnessAlongPath': the
// sum of their linear roughness, 1 for a diffuse event; non-finite counts as 0), the more its image
// is blurred, so it moves less with the camera: its length is compressed (d / (1 + d * k), k growing
// with roughness^2 and the bounce index) and its weight lowered. 'importance' is the share of the
// path's energy this segment brings, in [0, 1] (1 for the first bounce).
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
