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

// A tap as the stoppers need it, decoded once per texel.
struct Tap
{
    vec4 radianceVariance;
    vec3 Nw;          // World-space normal.
    float luminance;  // Of .rgb of radianceVariance.
    vec3 X;           // View-space position.
    float roughness;  // Linear roughness; -1: no surface (sky or outside the image).
};

// Every iteration reads its taps from shared memory. A group holds 8x8 pixels gAtrousStep apart
// (a strided tile): the image is cut into blocks of 8 * step pixels, each holding step x step such
// tiles, one per offset within a step. The taps of its pixels are then the texels of the same
// lattice, 2 * step around it: (8 + 4) x (8 + 4) texels, each decoded once (viewZ, normal and
// position, luminance) for the up to 25 taps and 9 variance taps that read it.
#define BORDER 2
#define REGION (RELAX_TILE_SIZE + 2 * BORDER)
shared vec4 sRadianceVariance[REGION * REGION];
shared vec4 sNormalLuminance[REGION * REGION];
shared vec4 sPositionRoughness[REGION * REGION];

// Pixel of the strided tile's texel 'lattice' (the group's pixels at [0, 8)).
ivec2 LatticePixel(ivec2 lattice, int step)
{
    ivec2 group = ivec2(gl_WorkGroupID.xy);
    ivec2 block = group / step, offset = group - block * step;
    return block * (RELAX_TILE_SIZE * step) + offset + lattice * step;
}

void Preload(int step)
{
    for (int i = int(gl_LocalInvocationIndex); i < REGION * REGION; i += RELAX_TILE_SIZE * RELAX_TILE_SIZE)
    {
        ivec2 p = LatticePixel(ivec2(i % REGION, i / REGION) - BORDER, step);
        RelaxSurface s = Relax_LoadNeighbour(gIn_NormalRoughness, gIn_ViewZ, p);
        vec4 radianceVariance = s.z == 0.0 ? vec4(0.0) : texelFetch(gIn_RadianceVariance, p, 0);
        sRadianceVariance[i] = radianceVariance;
        sNormalLuminance[i] = vec4(s.Nw, _NRD_Luminance(radianceVariance.rgb));
        sPositionRoughness[i] = vec4(s.X, s.z == 0.0 ? -1.0 : s.roughness);
    }
    barrier();
}

// The tap 'offset' steps from this invocation's pixel.
int RegionIndex(ivec2 offset)
{
    ivec2 local = ivec2(gl_LocalInvocationID.xy) + BORDER + offset;
    return local.y * REGION + local.x;
}

Tap LoadTap(ivec2 offset)
{
    int i = RegionIndex(offset);
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

void main()
{
    const int step = int(gAtrousStep);
    // Step 1: the group is a tile of the sky map. Larger steps: its pixels lie in step x step tiles,
    // and sky pixels return below.
    if (step == 1 && Relax_IsTileSkipped(gIn_Tiles))
        return;
    ivec2 pixel = LatticePixel(ivec2(gl_LocalInvocationID.xy), step);
    Preload(step);
    Tap c = LoadTap(ivec2(0));
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
            int t = RegionIndex(ivec2(i, j));
            float k = (i == 0 ? 0.5 : 0.25) * (j == 0 ? 0.5 : 0.25);
            if (sPositionRoughness[t].w < 0.0)
                continue;
            variance += k * sRadianceVariance[t].w;
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
                t = LoadTap(ivec2(i, j));
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
