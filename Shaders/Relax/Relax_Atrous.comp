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

struct Tap
{
    vec4 radianceVariance;
    RelaxSurface surface;
};

#if RELAX_ATROUS_SMEM
// Step 1: the group's 8x8 pixels and a border of 2 live in shared memory.
#define BORDER 2
#define REGION (RELAX_TILE_SIZE + 2 * BORDER)
shared vec4 sRadianceVariance[REGION * REGION];
shared vec4 sNormalZ[REGION * REGION];   // World-space normal, viewZ (0: sky or outside).
shared float sRoughness[REGION * REGION];

void Preload()
{
    ivec2 base = ivec2(gl_WorkGroupID.xy) * RELAX_TILE_SIZE - BORDER;
    for (uint i = gl_LocalInvocationIndex; i < REGION * REGION; i += RELAX_TILE_SIZE * RELAX_TILE_SIZE)
    {
        ivec2 p = base + ivec2(i % REGION, i / REGION);
        RelaxSurface s = Relax_LoadNeighbour(gIn_NormalRoughness, gIn_ViewZ, p);
        sNormalZ[i] = vec4(s.Nw, s.z);
        sRoughness[i] = s.roughness;
        sRadianceVariance[i] = s.z == 0.0 ? vec4(0.0) : texelFetch(gIn_RadianceVariance, p, 0);
    }
    barrier();
}

Tap LoadTap(ivec2 p)
{
    ivec2 local = p - (ivec2(gl_WorkGroupID.xy) * RELAX_TILE_SIZE - BORDER);
    Tap t;
    if (any(lessThan(local, ivec2(0))) || any(greaterThanEqual(local, ivec2(REGION))))
    {
        // Outside the preloaded region (cannot happen with step 1 and taps within BORDER): no tap.
        t.surface.N = vec3(0.0, 0.0, 1.0);
        t.surface.Nw = vec3(0.0, 0.0, 1.0);
        t.surface.z = 0.0;
        t.surface.X = vec3(0.0);
        t.surface.roughness = 1.0;
        t.radianceVariance = vec4(0.0);
        return t;
    }
    int i = local.y * REGION + local.x;
    vec4 nz = sNormalZ[i];
    t.surface.N = vec3(0.0, 0.0, 1.0);
    t.surface.Nw = nz.xyz;
    t.surface.z = nz.w;
    t.surface.X = nz.w == 0.0 ? vec3(0.0) : _NRD_ViewPosition(_NRD_PixelUv(p), nz.w);
    t.surface.roughness = sRoughness[i];
    t.radianceVariance = sRadianceVariance[i];
    return t;
}

// viewZ (0: no surface) and variance of a tap, for the variance prefilter.
vec2 LoadDepthVariance(ivec2 p)
{
    ivec2 local = p - (ivec2(gl_WorkGroupID.xy) * RELAX_TILE_SIZE - BORDER);
    if (any(lessThan(local, ivec2(0))) || any(greaterThanEqual(local, ivec2(REGION))))
        return vec2(0.0);
    int i = local.y * REGION + local.x;
    return vec2(sNormalZ[i].w, sRadianceVariance[i].w);
}
#else
Tap LoadTap(ivec2 p)
{
    Tap t;
    t.surface = Relax_LoadNeighbour(gIn_NormalRoughness, gIn_ViewZ, p);
    t.radianceVariance = t.surface.z == 0.0 ? vec4(0.0) : texelFetch(gIn_RadianceVariance, p, 0);
    return t;
}

vec2 LoadDepthVariance(ivec2 p)
{
    if (!Relax_IsInImage(p))
        return vec2(0.0);
    float z = texelFetch(gIn_ViewZ, p, 0).x;
    return _NRD_IsSky(z) ? vec2(0.0) : vec2(z, texelFetch(gIn_RadianceVariance, p, 0).w);
}
#endif

void main()
{
    if (Relax_IsTileSkipped(gIn_Tiles))
        return;
    ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
#if RELAX_ATROUS_SMEM
    Preload();
    const int step = 1;
#else
    const int step = int(gAtrousStep);
#endif
    Tap c = LoadTap(pixel);
    if (c.surface.z == 0.0)
        return;
    c.surface.N = Relax_ViewNormal(c.surface.Nw); // The tangent plane's normal.
    bool isLast = (gFlags & RELAX_FLAG_LAST_ATROUS) != 0u;

    // Variance prefiltered with a 3x3 Gaussian (1/4, 1/8, 1/16) of the neighbours on a surface.
    float variance = 0.0, varianceWeight = 0.0;
    for (int j = -1; j <= 1; j++)
        for (int i = -1; i <= 1; i++)
        {
            vec2 zv = LoadDepthVariance(pixel + ivec2(i, j) * step);
            float k = (i == 0 ? 0.5 : 0.25) * (j == 0 ? 0.5 : 0.25);
            if (zv.x == 0.0)
                continue;
            variance += k * zv.y;
            varianceWeight += k;
        }
    variance /= varianceWeight;

#if RELAX_SPECULAR
    float lobe = Relax_LobeHalfAngle(c.surface.roughness);
#else
    float lobe = Relax_LobeHalfAngle(1.0);
#endif
    float maxAngle = gLobeAngleFraction * lobe + gLobeAngleSlack;
    float lumaCenter = _NRD_Luminance(c.radianceVariance.rgb);
    float lumaScale = 1.0 / (gPhiLuminance * sqrt(max(variance, 0.0)) + 1e-6);
    const float kKernel[3] = float[3](3.0 / 8.0, 1.0 / 4.0, 1.0 / 16.0);

    vec3 sum = vec3(0.0);
    float varianceSum = 0.0, weightSum = 0.0, hitSum = 0.0;
    // Plain loops: unrolled, the 25 surface loads make the shader several times larger to compile.
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
                if (t.surface.z == 0.0)
                    continue;
                w = Relax_NormalWeight(c.surface.Nw, t.surface.Nw, maxAngle);
                w *= Relax_PlaneWeight(c.surface, t.surface.X, gDepthThreshold);
#if RELAX_SPECULAR
                if ((gFlags & RELAX_FLAG_ROUGHNESS_STOP) != 0u)
                    w *= Relax_RoughnessWeight(c.surface.roughness, t.surface.roughness, gRoughnessFraction);
#endif
                w *= exp(-abs(_NRD_Luminance(t.radianceVariance.rgb) - lumaCenter) * lumaScale);
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
