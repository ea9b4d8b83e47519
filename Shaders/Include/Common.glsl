// Shared math for all passes (private helpers, _NRD_ prefix where they could clash with app code).
#ifndef NRD_COMMON_GLSL
#define NRD_COMMON_GLSL

#include "NRD.glsl"

#define NRD_EPS 1e-6
#define NRD_PI 3.14159265358979

float _NRD_Luminance(vec3 c) { return dot(c, vec3(0.2126, 0.7152, 0.0722)); }

bool _NRD_IsFinite(float x) { return !isnan(x) && !isinf(x); }
bool _NRD_IsFinite(vec4 v) { return _NRD_IsFinite(v.x) && _NRD_IsFinite(v.y) && _NRD_IsFinite(v.z) && _NRD_IsFinite(v.w); }

vec4 _NRD_Sanitize(vec4 v, float replacement)
{
    return vec4(_NRD_Sanitize(v.x, replacement), _NRD_Sanitize(v.y, replacement), _NRD_Sanitize(v.z, replacement),
                _NRD_Sanitize(v.w, replacement));
}

// Largest value that survives RGBA16f storage; use before writing history in fp16 formats.
vec4 _NRD_ClampToHalf(vec4 v) { return clamp(v, vec4(-NRD_FP16_MAX), vec4(NRD_FP16_MAX)); }

// Hit distance in world units of a normalized hit distance (REBLUR_FrontEnd_GetNormHitDist's
// inverse below 1; 1 maps to the end of the normalization range). hitDistParams: the method's
// nrd::HitDistanceParameters (A, B, C, D).
float _NRD_GetHitDist(float normHitDist, float viewZ, vec4 hitDistParams, float roughness)
{
    return clamp(_NRD_Sanitize(normHitDist, 0.0), 0.0, 1.0) * _NRD_GetHitDistNormalization(viewZ, hitDistParams, roughness);
}

uint _NRD_Hash(uint x)
{
    x ^= x >> 16u; x *= 0x7feb352du;
    x ^= x >> 15u; x *= 0x846ca68bu;
    x ^= x >> 16u;
    return x;
}

float _NRD_Random01(uint seed) { return float(_NRD_Hash(seed) >> 8u) * (1.0 / 16777216.0); }

#endif
