#version 450
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_samplerless_texture_functions : require
#extension GL_EXT_control_flow_attributes : require

// RELAX a-trous iteration (SVGF section 4.3, Dammertz et al. 2010): 5x5 taps gAtrousStep pixels
// apart with the B3-spline kernel (1/16, 1/4, 3/8, 1/4, 1/16) per axis, each tap weighted by
//   luminance  exp(-|l - l'| / (gPhiLuminance * sqrt(3x3 Gaussian of the variance) + 1e-6)),
//   normal     max(0, 1 - angle(N, N') / (gLobeAngleFraction * lobe half-angle(roughness) + slack)),
//              the half-angle of roughness 1 for diffuse (Relax_LobeHalfAngle),
//   depth      max(0, 1 - |N . (X' - X)| / (gDepthThreshold * viewZ)), the distance to the tangent plane,
//   roughness  (specular, RELAX_FLAG_ROUGHNESS_STOP) max(0, 1 - |r - r'| / (gRoughnessFraction * r + 0.01)).
// The variance is filtered with the squared weights for the next iteration. The last iteration
// writes (radiance, hit distance) to the output, the hit distance filtered with the same weights.
// Sky pixels are neither read nor written.
#include "Bindings.glsl"
#include "Relax_Constants.h"
#include "Relax_Atrous.resources.h"
#include "CommonFrame.glsl"
#include "Relax_Common.glsl"

#ifndef RELAX_ATROUS_SMEM
#define RELAX_ATROUS_SMEM 0
#endif

// A tap as the stoppers need it, decoded once per texel.
struct Tap
{
    vec4 radianceVariance;
    vec3 Nw;          // World-space normal.
    float luminance;  // Of .rgb of radianceVariance.
    vec3 X;           // View-space position.
    float roughness;  // Linear roughness; -1: no surface (sky or outside the image).
};

Tap DecodeTap(ivec2 p)
{
    RelaxSurface s = Relax_LoadNeighbour(gIn_NormalRoughness, gIn_ViewZ, p);
    Tap t;
    t.Nw = s.Nw;
    t.X = s.X;
    t.roughness = s.z == 0.0 ? -1.0 : s.roughness;
    t.radianceVariance = s.z == 0.0 ? vec4(0.0) : texelFetch(gIn_RadianceVariance, p, 0);
    t.luminance = _NRD_Luminance(t.radianceVariance.rgb);
    return t;
}

#if RELAX_ATROUS_SMEM
// Steps 1 and 2: the group's 8x8 pixels and a border of 2 * step live in shared memory, each texel
// decoded once (viewZ, normal and position, luminance) for the up to 25 taps and 9 variance taps
// that read it.
#define MAX_BORDER 4
#define MAX_REGION (RELAX_TILE_SIZE + 2 * MAX_BORDER)
shared vec4 sRadianceVariance[MAX_REGION * MAX_REGION];
shared vec4 sNormalLuminance[MAX_REGION * MAX_REGION];
shared vec4 sPositionRoughness[MAX_REGION * MAX_REGION];
int gRegion;   // 8 + 4 * step texels per row.
ivec2 gOrigin; // Pixel of the region's first texel.

void Preload(int step)
{
    gRegion = RELAX_TILE_SIZE + 4 * step;
    gOrigin = ivec2(gl_WorkGroupID.xy) * RELAX_TILE_SIZE - 2 * step;
    for (int i = int(gl_LocalInvocationIndex); i < gRegion * gRegion; i += RELAX_TILE_SIZE * RELAX_TILE_SIZE)
    {
        Tap t = DecodeTap(gOrigin + ivec2(i % gRegion, i / gRegion));
        sRadianceVariance[i] = t.radianceVariance;
        sNormalLuminance[i] = vec4(t.Nw, t.luminance);
        sPositionRoughness[i] = vec4(t.X, t.roughness);
    }
    barrier();
}

// Every tap of a pixel of the group lies within the region (taps at most 2 * step away).
int RegionIndex(ivec2 p)
{
    ivec2 local = p - gOrigin;
    return local.y * gRegion + local.x;
}

Tap LoadTap(ivec2 p)
{
    int i = RegionIndex(p);
    Tap t;
    t.radianceVariance = sRadianceVariance[i];
    vec4 nl = sNormalLuminance[i];
    t.Nw = nl.xyz;
    t.luminance = nl.w;
    vec4 xr = sPositionRoughness[i];
    t.X = xr.xyz;
    t.roughness = xr.w;
    return t;
}

// Whether a tap holds a surface, and its variance, for the variance prefilter.
vec2 LoadSurfaceVariance(ivec2 p)
{
    int i = RegionIndex(p);
    return vec2(sPositionRoughness[i].w, sRadianceVariance[i].w);
}
#else
Tap LoadTap(ivec2 p) { return DecodeTap(p); }

vec2 LoadSurfaceVariance(ivec2 p)
{
    if (!Relax_IsInImage(p))
        return vec2(-1.0, 0.0);
    float z = texelFetch(gIn_ViewZ, p, 0).x;
    return _NRD_IsSky(z) ? vec2(-1.0, 0.0) : vec2(0.0, texelFetch(gIn_RadianceVariance, p, 0).w);
}
#endif

void main()
{
    if (Relax_IsTileSkipped(gIn_Tiles))
        return;
    ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
    const int step = int(gAtrousStep);
#if RELAX_ATROUS_SMEM
    Preload(step);
#endif
    Tap c = LoadTap(pixel);
    if (c.roughness < 0.0)
        return;
    vec3 N = Relax_ViewNormal(c.Nw); // The tangent plane's normal.
    float z = c.X.z * gViewZSign;
    bool isLast = (gFlags & RELAX_FLAG_LAST_ATROUS) != 0u;

    // Variance prefiltered with a 3x3 Gaussian (1/4, 1/8, 1/16) of the neighbours on a surface.
    float variance = 0.0, varianceWeight = 0.0;
    for (int j = -1; j <= 1; j++)
        for (int i = -1; i <= 1; i++)
        {
            vec2 sv = LoadSurfaceVariance(pixel + ivec2(i, j) * step);
            float k = (i == 0 ? 0.5 : 0.25) * (j == 0 ? 0.5 : 0.25);
            if (sv.x < 0.0)
                continue;
            variance += k * sv.y;
            varianceWeight += k;
        }
    variance /= varianceWeight;

#if RELAX_SPECULAR
    float lobe = Relax_LobeHalfAngle(c.roughness);
    bool roughnessStop = (gFlags & RELAX_FLAG_ROUGHNESS_STOP) != 0u;
    float roughnessScale = 1.0 / (gRoughnessFraction * c.roughness + 0.01);
#else
    float lobe = Relax_LobeHalfAngle(1.0);
#endif
    // The stoppers of Relax_Common.glsl with their divisions hoisted out of the loop.
    float angleScale = 1.0 / (gLobeAngleFraction * lobe + gLobeAngleSlack);
    float planeScale = 1.0 / (gDepthThreshold * z);
    float lumaScale = 1.0 / (gPhiLuminance * sqrt(max(variance, 0.0)) + 1e-6);
    const float kKernel[3] = float[3](3.0 / 8.0, 1.0 / 4.0, 1.0 / 16.0);

    vec3 sum = vec3(0.0);
    float varianceSum = 0.0, weightSum = 0.0, hitSum = 0.0;
    // Plain loops: unrolled, the 25 tap loads make the shader several times larger to compile.
    for (int j = -2; j <= 2; j++)
        for (int i = -2; i <= 2; i++)
        {
            ivec2 q = pixel + ivec2(i, j) * step;
            float w;
            Tap t;
            if (i == 0 && j == 0)
            {
                t = c;
                w = 1.0;
            }
            else
            {
                t = LoadTap(q);
                if (t.roughness < 0.0)
                    continue;
                w = clamp(1.0 - acos(clamp(dot(c.Nw, t.Nw), -1.0, 1.0)) * angleScale, 0.0, 1.0);
                w *= clamp(1.0 - abs(dot(N, t.X - c.X)) * planeScale, 0.0, 1.0);
#if RELAX_SPECULAR
                if (roughnessStop)
                    w *= clamp(1.0 - abs(c.roughness - t.roughness) * roughnessScale, 0.0, 1.0);
#endif
                w *= exp(-abs(t.luminance - c.luminance) * lumaScale);
            }
            w *= kKernel[abs(i)] * kKernel[abs(j)];
            if (w <= 0.0)
                continue;
            sum += w * t.radianceVariance.rgb;
            varianceSum += w * w * t.radianceVariance.w;
            weightSum += w;
            if (isLast)
                hitSum += w * texelFetch(gIn_HitDist, q, 0).w;
        }
    vec3 radiance = sum / weightSum;
    if (isLast)
        imageStore(gOut, pixel, _NRD_ClampToHalf(vec4(radiance, hitSum / weightSum)));
    else
        imageStore(gOut, pixel, _NRD_ClampToHalf(vec4(radiance, varianceSum / (weightSum * weightSum))));
}
