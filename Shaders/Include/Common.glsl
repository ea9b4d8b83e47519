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

// 'x', a blend of an fp16 'history' towards 'target'; where it lies less than one fp16 step from the
// history, the next fp16 value towards the target instead. A history that blends a fraction of the
// way towards a constant input each frame then reaches it exactly; stored as it is, the step would
// round back onto the history once it is below half an fp16 step (a lit pixel's history of
// 1 - 2^-11 blended by 1/6 towards 1 stays 1 - 2^-11), or below a whole one where stores round
// towards zero (some GPUs do). Larger steps are left to the store's rounding.
uint _NRD_Fp16StepUp(uint h) { return (h & 0x8000u) == 0u ? h + 1u : (h == 0x8000u ? 1u : h - 1u); }
uint _NRD_Fp16StepDown(uint h) { return (h & 0x8000u) != 0u ? h + 1u : (h == 0u ? 0x8001u : h - 1u); }
float _NRD_Fp16Converge(float x, float history, float target)
{
    uint h = packHalf2x16(vec2(history, 0.0)) & 0xFFFFu;
    float stored = unpackHalf2x16(h).x;
    if (target == stored || x == stored)
        return x;
    bool isUp = target > stored;
    float next = unpackHalf2x16(isUp ? _NRD_Fp16StepUp(h) : _NRD_Fp16StepDown(h)).x;
    return (isUp ? x < next : x > next) ? next : x;
}
vec4 _NRD_Fp16Converge(vec4 x, vec4 history, vec4 target)
{
    return vec4(_NRD_Fp16Converge(x.x, history.x, target.x), _NRD_Fp16Converge(x.y, history.y, target.y),
                _NRD_Fp16Converge(x.z, history.z, target.z), _NRD_Fp16Converge(x.w, history.w, target.w));
}

// The fp16 value nearest to 'x' (finite, within the fp16 range): stored, it stays as it is whatever
// the store's rounding. A filter's output a few fp32 ulps under 1 (a lit pixel that took 3e-5 of a
// shadowed neighbour) otherwise reads 1 - 2^-11 where stores round towards zero.
float _NRD_NearestFp16(float x)
{
    uint h = packHalf2x16(vec2(x, 0.0)) & 0xFFFFu;
    float a = unpackHalf2x16(h).x;
    float b = unpackHalf2x16(x > a ? _NRD_Fp16StepUp(h) : _NRD_Fp16StepDown(h)).x;
    return abs(b - x) < abs(a - x) ? b : a;
}
vec4 _NRD_NearestFp16(vec4 v)
{
    return vec4(_NRD_NearestFp16(v.x), _NRD_NearestFp16(v.y), _NRD_NearestFp16(v.z), _NRD_NearestFp16(v.w));
}

// Fraction of a disk's area on the far side of a chord, the chord at signed distance 'x' (in radii)
// from the centre on the near side (x <= -1: none of it; 0: half; >= 1: all). A light's disk cut by a
// surface's tangent plane: x = cos(angle between the normal and the light's direction) / sin(the
// light's angular radius) gives the part of the disk above the plane.
float _NRD_DiskFractionBeyondChord(float x)
{
    x = isnan(x) ? 0.0 : clamp(x, -1.0, 1.0); // +-Inf: all or none.
    return clamp(0.5 + (x * sqrt(1.0 - x * x) + asin(x)) * (1.0 / NRD_PI), 0.0, 1.0);
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
